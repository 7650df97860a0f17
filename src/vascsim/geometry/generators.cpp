#include "vascsim/geometry/generators.hpp"

#include <fmt/format.h>
#include <cmath>
#include <numbers>
#include <random>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/kuhn.hpp"

namespace vascsim {

namespace {

// Appends the 6 tets of one hexahedral cell whose corner with bit mask m has node index corner[m];
// orients every tet positively using the node positions.
void add_cell_tets(const std::array<Index, 8>& corner, const Vec3Array& X, std::vector<Tet>& tets) {
  for (const auto& t : kKuhnTets) {
    Tet tet{corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]};
    if (signed_volume(X[tet[0]], X[tet[1]], X[tet[2]], X[tet[3]]) < 0.0) std::swap(tet[2], tet[3]);
    tets.push_back(tet);
  }
}

}  // namespace

NodeCloud make_box(const BoxSpec& spec) {
  const Vec3 extent = spec.max_m - spec.min_m;
  if (!(extent.array() > 0.0).all()) throw InputError("box: max must exceed min along every axis");
  if ((spec.cells.array() < 1).any()) throw InputError("box: at least one cell per axis is needed");
  if (!(spec.jitter >= 0.0 && spec.jitter < 0.3)) throw InputError("box: jitter must be in [0, 0.3)");
  const Eigen::Vector3i n = spec.cells + Eigen::Vector3i::Ones();
  const Vec3 step = extent.cwiseQuotient(spec.cells.cast<double>());
  NodeCloud cloud;
  cloud.kind = "box";
  cloud.spacing_m = step.minCoeff();
  cloud.box = Eigen::AlignedBox3d(spec.min_m, spec.max_m);
  cloud.box_cells = spec.cells;
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  auto id = [&](int i, int j, int k) { return static_cast<Index>(i + n[0] * (j + n[1] * k)); };
  cloud.positions.reserve(static_cast<std::size_t>(n.prod()));
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        cloud.positions.push_back(spec.min_m + Vec3(i * step[0], j * step[1], k * step[2]));
  // Tets are oriented on the regular lattice, then the nodes are jittered: a jitter that inverts a
  // tet is an error, never silently "fixed" by re-orienting it (that would overlap its neighbours).
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i) {
        std::array<Index, 8> c;
        for (int m = 0; m < 8; ++m) c[m] = id(i + (m & 1), j + ((m >> 1) & 1), k + ((m >> 2) & 1));
        add_cell_tets(c, cloud.positions, cloud.tets);
      }
  if (spec.jitter > 0.0) {
    for (auto& p : cloud.positions) p += spec.jitter * step.cwiseProduct(Vec3(uni(rng), uni(rng), uni(rng)));
    for (const Tet& t : cloud.tets)
      if (!(signed_volume(cloud.positions[t[0]], cloud.positions[t[1]], cloud.positions[t[2]],
                          cloud.positions[t[3]]) > 0.0))
        throw InputError(
            fmt::format("box: jitter {} inverts a virtual tetrahedron (seed {}); use a smaller jitter "
                        "(<= 0.2 is always safe in practice) or another seed",
                        spec.jitter, spec.seed));
  }
  return cloud;
}

double lattice_phase_rad(double lattice_angle_deg, int columns) {
  const double step = 360.0 / columns;
  const double phase = lattice_angle_deg - step * std::round(lattice_angle_deg / step);
  // Rounding of an angle that is already a multiple of the step must not turn the lattice.
  return std::abs(phase) < 1e-9 * step ? 0.0 : phase * std::numbers::pi / 180.0;
}

int lattice_columns(double r_mid_m, double spacing_m, int asked) {
  return std::max(
      8, asked > 0 ? asked : static_cast<int>(std::lround(2.0 * std::numbers::pi * r_mid_m / spacing_m)));
}

int lattice_cross_sections(double length_m, double spacing_m, int asked) {
  return std::max(2, asked > 0 ? asked : static_cast<int>(std::lround(length_m / spacing_m)) + 1);
}

NodeCloud make_tube(const TubeSpec& s) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InputError("tube: " + what);
  };
  require(s.outer_radius_m > 0.0, "outer radius must be > 0");
  require(s.wall_thickness_m > 0.0 && s.wall_thickness_m < s.outer_radius_m,
          "wall thickness must be > 0 and < outer radius");
  require(s.length_m > 0.0, "length must be > 0");
  require(s.node_spacing_m > 0.0, "node spacing must be > 0");
  require(s.min_layers >= 2, "at least 2 layers through the wall are needed");
  require(std::isfinite(s.lattice_angle_deg), "lattice angle must be finite");
  const double r_in = s.outer_radius_m - s.wall_thickness_m;
  const double r_mid = 0.5 * (r_in + s.outer_radius_m);
  const int nr =
      std::max(s.min_layers, static_cast<int>(std::ceil(s.wall_thickness_m / s.node_spacing_m - 1e-9)) + 1);
  const int nt = lattice_columns(r_mid, s.node_spacing_m, s.angular_nodes);
  const int nz = lattice_cross_sections(s.length_m, s.node_spacing_m, s.axial_nodes);
  const double total = static_cast<double>(nr) * nt * nz;
  require(total <= 5e7,
          fmt::format("{:.0f} nodes requested; the limit is 5e7 (increase node_spacing_m)", total));

  NodeCloud cloud;
  cloud.kind = "tube";
  cloud.spacing_m = s.node_spacing_m;
  cloud.tube = TubeShape{s.outer_radius_m, r_in, s.length_m, nr};
  cloud.wall_lattice = WallLatticeNumbering{nr, nt, nz};
  auto id = [&](int ir, int it, int iz) { return static_cast<Index>(ir + nr * ((it % nt) + nt * iz)); };
  const double phase = lattice_phase_rad(s.lattice_angle_deg, nt);
  cloud.positions.resize(static_cast<std::size_t>(total));
  for (int iz = 0; iz < nz; ++iz)
    for (int it = 0; it < nt; ++it)
      for (int ir = 0; ir < nr; ++ir) {
        const double r = r_in + s.wall_thickness_m * ir / (nr - 1);
        const double th = 2.0 * std::numbers::pi * it / nt + phase;
        const double z = s.length_m * iz / (nz - 1);
        cloud.positions[id(ir, it, iz)] = Vec3(r * std::cos(th), r * std::sin(th), z);
      }
  for (int iz = 0; iz + 1 < nz; ++iz)
    for (int it = 0; it < nt; ++it)
      for (int ir = 0; ir + 1 < nr; ++ir) {
        std::array<Index, 8> c;
        for (int m = 0; m < 8; ++m) c[m] = id(ir + (m & 1), it + ((m >> 1) & 1), iz + ((m >> 2) & 1));
        add_cell_tets(c, cloud.positions, cloud.tets);
      }
  return cloud;
}

}  // namespace vascsim
