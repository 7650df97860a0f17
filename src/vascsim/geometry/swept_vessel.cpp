#include "vascsim/geometry/swept_vessel.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/generators.hpp"
#include "vascsim/geometry/graded_axis.hpp"
#include "vascsim/geometry/kuhn.hpp"

namespace vascsim {

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw InputError("swept vessel: " + what);
}

void check_spec(const Centerline& cl, const SweptVesselSpec& s) {
  if (!(std::isfinite(s.outer_radius_m) && s.outer_radius_m > 0.0))
    fail("outer radius must be finite and > 0");
  if (!(std::isfinite(s.wall_thickness_m) && s.wall_thickness_m > 0.0 &&
        s.wall_thickness_m < s.outer_radius_m))
    fail("wall thickness must be > 0 and < outer radius");
  if (!(std::isfinite(s.node_spacing_m) && s.node_spacing_m > 0.0))
    fail("node spacing must be finite and > 0");
  if (s.min_layers < 3)
    fail(
        "at least 3 node layers through the wall are needed (docs/model/00-design-decisions.md, hollow "
        "vessels)");
  if (!std::isfinite(s.lattice_angle_deg)) fail("lattice angle must be finite");
  if (s.refine.enabled) {
    const WallRefinement& r = s.refine;
    if (!(r.node_spacing_m > 0.0 && r.node_spacing_m <= s.node_spacing_m))
      fail(fmt::format("the refined spacing {:.4g} m must be > 0 and at most the node spacing {:.4g} m",
                       r.node_spacing_m, s.node_spacing_m));
    if (!(r.angle_half_width_deg > 0.0 && r.s_half_length_m > 0.0 && r.margin_m >= 0.0))
      fail("the refined window needs a half width > 0 deg, a half length > 0 m and a margin >= 0 m");
    if (s.angular_nodes > 0 || s.axial_nodes > 0)
      fail("a graded lattice chooses its own counts; leave them out");
  }
  if (!(cl.min_radius_of_curvature() > s.outer_radius_m))
    fail(fmt::format(
        "the centre-line's smallest radius of curvature {:.6g} m must exceed the outer radius {:.6g} m "
        "(the wall would fold over itself)",
        cl.min_radius_of_curvature(), s.outer_radius_m));
}

// The (r, theta, s) lattice of the sweep: nr layers through the wall, nt around, nz along the centre-line.
struct SweepLattice {
  int nr = 0, nt = 0, nz = 0;
  double r_in = 0.0, length = 0.0, phase = 0.0;
  std::vector<double> theta, cos_t, sin_t;  // per angular index, rad
  std::vector<double> s;                    // per axial index, m
  std::vector<Frame> frames;                // per axial index (rotation-minimising)
  bool graded = false;
  Index id(int ir, int it, int iz) const { return static_cast<Index>(ir + nr * ((it % nt) + nt * iz)); }
  double s_at(int iz) const { return s[static_cast<std::size_t>(iz)]; }
  Vec3 radial(int it, int iz) const {
    const Frame& f = frames[static_cast<std::size_t>(iz)];
    return cos_t[static_cast<std::size_t>(it)] * f.N + sin_t[static_cast<std::size_t>(it)] * f.B;
  }
};

// The graded lattice's columns (angles, rad) and cross-sections (arc lengths, m): fine over the window and
// its margin, graded outside (graded_axis.hpp); around the centre-line as arc length at the mid-wall radius.
void graded_axes(const SweptVesselSpec& s, double r_mid, SweepLattice& g) {
  const WallRefinement& r = s.refine;
  const AxisGrading grading{r.node_spacing_m, s.node_spacing_m, r.growth};
  const double c = r.angle_center_deg * std::numbers::pi / 180.0 * r_mid,
               w = r.angle_half_width_deg * std::numbers::pi / 180.0 * r_mid;
  if (!(2.0 * (w + r.margin_m) < 2.0 * std::numbers::pi * r_mid))
    fail("the refined window and its margins go all the way round the vessel; use a uniform lattice");
  const std::vector<double> around = graded_circle(
      2.0 * std::numbers::pi * r_mid, {c - w - r.margin_m, c - w, c + w, c + w + r.margin_m}, grading);
  for (double x : around) g.theta.push_back(x / r_mid);
  g.s = graded_line(g.length,
                    {r.s_center_m - r.s_half_length_m - r.margin_m, r.s_center_m - r.s_half_length_m,
                     r.s_center_m + r.s_half_length_m, r.s_center_m + r.s_half_length_m + r.margin_m},
                    grading);
  g.nt = static_cast<int>(g.theta.size());
  g.nz = static_cast<int>(g.s.size());
}

SweepLattice sweep_lattice(const Centerline& cl, const SweptVesselSpec& s) {
  SweepLattice g;
  g.r_in = s.outer_radius_m - s.wall_thickness_m;
  const double r_mid = 0.5 * (g.r_in + s.outer_radius_m);
  g.length = cl.length();
  // Layers follow the finest spacing along the wall.
  const double across = s.refine.enabled ? s.refine.node_spacing_m : s.node_spacing_m;
  g.nr = std::max(s.min_layers, static_cast<int>(std::ceil(s.wall_thickness_m / across - 1e-9)) + 1);
  g.graded = s.refine.enabled;
  if (g.graded) {
    graded_axes(s, r_mid, g);
    if (!(static_cast<double>(g.nr) * g.nt * g.nz <= 5e7))
      fail("more than 5e7 nodes requested (coarsen the spacings)");
  } else {
    g.nt = lattice_columns(r_mid, s.node_spacing_m, s.angular_nodes);
    const double nz_real = g.length / s.node_spacing_m;
    if (!(static_cast<double>(g.nr) * g.nt * (nz_real + 1.0) <= 5e7))
      fail("more than 5e7 nodes requested (increase node_spacing_m)");
    g.nz = lattice_cross_sections(g.length, s.node_spacing_m, s.axial_nodes);
    g.phase = lattice_phase_rad(s.lattice_angle_deg, g.nt);
    for (int it = 0; it < g.nt; ++it) g.theta.push_back(2.0 * std::numbers::pi * it / g.nt + g.phase);
    for (int iz = 0; iz < g.nz; ++iz) g.s.push_back(g.length * iz / (g.nz - 1));
  }
  g.cos_t.resize(static_cast<std::size_t>(g.nt));
  g.sin_t.resize(static_cast<std::size_t>(g.nt));
  for (int it = 0; it < g.nt; ++it) {
    const double th = g.theta[static_cast<std::size_t>(it)];
    g.cos_t[static_cast<std::size_t>(it)] = std::cos(th);
    g.sin_t[static_cast<std::size_t>(it)] = std::sin(th);
  }
  g.frames.resize(static_cast<std::size_t>(g.nz));
  for (int iz = 0; iz < g.nz; ++iz) g.frames[static_cast<std::size_t>(iz)] = cl.frame(g.s_at(iz));
  return g;
}

void sweep_nodes(const Centerline& cl, const SweptVesselSpec& s, const SweepLattice& g, NodeCloud& cloud) {
  cloud.positions.resize(static_cast<std::size_t>(g.nr) * g.nt * g.nz);
  for (int iz = 0; iz < g.nz; ++iz) {
    const Vec3 c = cl.position(g.s_at(iz));
    for (int it = 0; it < g.nt; ++it) {
      const Vec3 dir = g.radial(it, iz);
      for (int ir = 0; ir < g.nr; ++ir) {
        const double r = g.r_in + s.wall_thickness_m * ir / (g.nr - 1);
        cloud.positions[static_cast<std::size_t>(g.id(ir, it, iz))] = c + r * dir;
      }
    }
  }
}

// Oriented in lattice coordinates (r, theta, s): the map to space has positive Jacobian wherever r kappa < 1,
// so orienting there and checking after the mapping never hides an inversion.
void sweep_tets(const SweepLattice& g, NodeCloud& cloud) {
  const auto swap = kuhn_needs_swap();
  cloud.tets.reserve(static_cast<std::size_t>(6) * (g.nr - 1) * g.nt * (g.nz - 1));
  const Vec3Array& X = cloud.positions;
  for (int iz = 0; iz + 1 < g.nz; ++iz)
    for (int it = 0; it < g.nt; ++it)
      for (int ir = 0; ir + 1 < g.nr; ++ir) {
        std::array<Index, 8> c;
        for (int m = 0; m < 8; ++m) c[m] = g.id(ir + (m & 1), it + ((m >> 1) & 1), iz + ((m >> 2) & 1));
        for (std::size_t k = 0; k < kKuhnTets.size(); ++k) {
          const auto& q = kKuhnTets[k];
          Tet tet{c[q[0]], c[q[1]], c[q[2]], c[q[3]]};
          if (swap[k]) std::swap(tet[2], tet[3]);
          const double v = signed_volume(X[tet[0]], X[tet[1]], X[tet[2]], X[tet[3]]);
          if (!(v > 0.0))
            fail(fmt::format(
                "virtual tetrahedron {} (Kuhn tet {} of lattice cell radial {}, angular {}, axial {} at "
                "s = {:.6g} m) has volume {:.3g} m^3 <= 0 after sweeping; the bend is too tight for this "
                "outer radius and node spacing",
                cloud.tets.size(), k, ir, it, iz, g.s_at(iz), v));
          cloud.tets.push_back(tet);
        }
      }
}

// Surface: outer layer (ir = nr-1) then inner layer (ir = 0), shared by the end rings.
void sweep_surface(const SweepLattice& g, SweptVessel& out) {
  const int nt = g.nt, nz = g.nz;
  const Vec3Array& X = out.cloud.positions;
  const std::size_t nsurf = static_cast<std::size_t>(nt) * nz;
  out.surface_vertices.resize(2 * nsurf);
  out.normals.resize(2 * nsurf);
  out.uv.resize(2 * nsurf);
  auto outer = [&](int it, int iz) { return static_cast<Index>((it % nt) + nt * iz); };
  auto inner = [&](int it, int iz) { return static_cast<Index>(nsurf) + outer(it, iz); };
  for (int iz = 0; iz < nz; ++iz)
    for (int it = 0; it < nt; ++it) {
      const Vec3 dir = g.radial(it, iz);
      const double u = g.graded ? g.s_at(iz) / g.length : static_cast<double>(iz) / (nz - 1);
      const Eigen::Vector2d uv(u, static_cast<double>(it) / nt);
      const auto o = static_cast<std::size_t>(outer(it, iz));
      const auto i = static_cast<std::size_t>(inner(it, iz));
      out.surface_vertices[o] = X[static_cast<std::size_t>(g.id(g.nr - 1, it, iz))];
      out.surface_vertices[i] = X[static_cast<std::size_t>(g.id(0, it, iz))];
      // For an RMF sweep dX/ds is parallel to T, so the radial direction is the exact surface normal.
      out.normals[o] = dir;
      out.normals[i] = -dir;
      out.uv[o] = uv;
      out.uv[i] = uv;
    }
  auto& tri = out.triangles;
  tri.reserve(4 * nsurf + 4 * static_cast<std::size_t>(nt));
  for (int iz = 0; iz + 1 < nz; ++iz)
    for (int it = 0; it < nt; ++it) {
      // (theta step) x (s step) points outward: e_theta x T = e_r.
      const Index a = outer(it, iz), b = outer(it + 1, iz), c = outer(it + 1, iz + 1), d = outer(it, iz + 1);
      tri.push_back({a, b, c});
      tri.push_back({a, c, d});
      const Index ai = inner(it, iz), bi = inner(it + 1, iz), ci = inner(it + 1, iz + 1),
                  di = inner(it, iz + 1);
      tri.push_back({ai, ci, bi});
      tri.push_back({ai, di, ci});
    }
  for (int it = 0; it < nt; ++it) {
    // Start ring faces -T, end ring faces +T.
    tri.push_back({outer(it, 0), inner(it, 0), inner(it + 1, 0)});
    tri.push_back({outer(it, 0), inner(it + 1, 0), outer(it + 1, 0)});
    tri.push_back({outer(it, nz - 1), inner(it + 1, nz - 1), inner(it, nz - 1)});
    tri.push_back({outer(it, nz - 1), outer(it + 1, nz - 1), inner(it + 1, nz - 1)});
  }
}

}  // namespace

SweptVessel make_swept_vessel(const Centerline& cl, const SweptVesselSpec& s) {
  check_spec(cl, s);
  const SweepLattice g = sweep_lattice(cl, s);
  SweptVessel out;
  out.length_m = g.length;
  out.radial_layers = g.nr;
  out.angular_nodes = g.nt;
  out.axial_nodes = g.nz;
  out.angle_phase_rad = g.phase;
  out.graded = s.refine.enabled;
  out.theta_rad = g.theta;
  out.s_m = g.s;
  for (int it = 0; it < g.nt; ++it) {
    // As the uniform lattice always computed it (its regions select by these angles).
    const double deg = out.graded ? g.theta[static_cast<std::size_t>(it)] * 180.0 / std::numbers::pi
                                  : 360.0 * it / g.nt + g.phase * 180.0 / std::numbers::pi;
    const double wrapped = std::fmod(deg, 360.0);
    out.theta_deg.push_back(wrapped < 0.0 ? wrapped + 360.0 : wrapped);
  }
  out.cloud.kind = "swept_vessel";
  out.cloud.wall_lattice = WallLatticeNumbering{g.nr, g.nt, g.nz};
  out.cloud.spacing_m = s.node_spacing_m;
  sweep_nodes(cl, s, g, out.cloud);
  sweep_tets(g, out.cloud);
  sweep_surface(g, out);
  return out;
}

}  // namespace vascsim
