#include "vascsim/model/mass_spring_model.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <map>

#include "vascsim/constraints/dihedral_angle.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/spatial_grid.hpp"

namespace vascsim {

MassSpringSettings read_mass_spring_settings(JsonReader& b) {
  MassSpringSettings s;
  s.frames = read_baseline_frames(b);
  s.shell_thickness_m = b.number("shell_thickness_m", 0.0, 0.0, 1.0);
  s.flexion_scale = b.number("flexion_scale", 1.0, 0.0, 1e6);
  s.damping_ratio = b.number("damping_ratio", 0.05, 0.0, 10.0);
  s.damping_per_s = b.number("damping_per_s", 0.0, 0.0, 1e7);
  s.time_step_safety = b.number("time_step_safety", 0.5, 0.01, 1.0);
  s.map_neighbours = b.integer("map_neighbours", 4, 1, 64);
  b.finish();
  return s;
}

ModelEntry mass_spring_model_entry() {
  return make_baseline_entry<MassSpringModel, MassSpringSettings>(
      "mass_spring",
      "baseline [8] Li et al. 2018: surface mass-spring with flexion springs, semi-implicit Euler",
      &read_mass_spring_settings);
}

MassSpringModel::MassSpringModel(const Problem& problem, const MassSpringSettings& settings)
    : DynamicBaseline(problem, "mass_spring", settings.frames), settings_(settings) {
  const Discretization& disc = problem.discretization();
  const Vec3Array& X = disc.rest_positions();
  const std::vector<Triangle> faces = boundary_faces(disc.tets());
  if (faces.empty()) throw InputError("mass_spring: the body has no surface (no tetrahedra)");
  on_surface_.assign(X.size(), 0);
  for (const Triangle& f : faces)
    for (Index v : f) on_surface_[v] = 1;
  const std::vector<double> area = lumped_boundary_area(X, faces, std::vector<char>(X.size(), 1));
  double total_area = 0.0;
  for (double a : area) total_area += a;
  thickness_ = settings.shell_thickness_m > 0.0 ? settings.shell_thickness_m : disc.tet_volume() / total_area;
  mass_.assign(X.size(), 0.0);
  for (std::size_t i = 0; i < X.size(); ++i) mass_[i] = disc.material().density_kg_m3 * thickness_ * area[i];
  build_springs(faces);
  build_map();
  double omega2 = 0.0, gamma = 0.0;
  std::vector<double> k_rows(X.size(), 0.0), c_rows(X.size(), 0.0);
  springs_.add_row_sums(0.0, k_rows, c_rows);
  add_hinge_rows(k_rows);
  max_rates(mass_, k_rows, c_rows, omega2, gamma);
  const double dt_max =
      symplectic_euler_step(omega2, gamma + settings.damping_per_s, settings.time_step_safety);
  substeps_ = std::max(1, static_cast<int>(std::ceil(h_ / dt_max - 1e-9)));
  dt_ = h_ / substeps_;
  f_.assign(X.size(), Vec3::Zero());
  spdlog::info(
      "mass_spring: {} surface nodes of {}, shell t_s = {:.4g} m, {} structural springs + {} flexion hinges, "
      "dt {:.4g} s ({} substeps per frame)",
      std::count(on_surface_.begin(), on_surface_.end(), 1), X.size(), thickness_, structural_, flexion_, dt_,
      substeps_);
}

void MassSpringModel::build_springs(const std::vector<Triangle>& faces) {
  const Discretization& disc = problem_.discretization();
  const Vec3Array& X = disc.rest_positions();
  const double E = disc.material().youngs_modulus_pa, nu = disc.material().poisson_ratio;
  const double D = E * std::pow(thickness_, 3) / (12.0 * (1.0 - nu * nu));
  // Per surface edge (lo, hi): its triangles' areas and opposite vertices, the one in which the edge runs
  // lo -> hi first (dihedral_angle.hpp needs the triangles oriented alike: then x_3 = lo, x_4 = hi).
  struct EdgeFaces {
    double area = 0.0;
    std::vector<Index> opposite;
  };
  std::map<Edge, EdgeFaces> edges;
  for (const Triangle& f : faces) {
    const double A = 0.5 * (X[f[1]] - X[f[0]]).cross(X[f[2]] - X[f[0]]).norm();
    for (int k = 0; k < 3; ++k) {
      const Index a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      EdgeFaces& ef = edges[{std::min(a, b), std::max(a, b)}];
      ef.area += A;
      if (a < b)
        ef.opposite.insert(ef.opposite.begin(), c);
      else
        ef.opposite.push_back(c);
    }
  }
  auto reduced_mass = [&](Index a, Index b) { return mass_[a] * mass_[b] / (mass_[a] + mass_[b]); };
  for (const auto& [e, ef] : edges) {
    const double k = E * thickness_ * ef.area / (X[e[0]] - X[e[1]]).squaredNorm();
    springs_.add(X, e[0], e[1], k, 2.0 * settings_.damping_ratio * std::sqrt(k * reduced_mass(e[0], e[1])));
    ++structural_;
    if (settings_.flexion_scale <= 0.0 || ef.opposite.size() != 2)
      continue;  // closed surface: two faces per edge
    Hinge hg{ef.opposite[0], ef.opposite[1], e[0], e[1], 0.0, 0.0};
    hg.theta0 = constraints::dihedral_angle(X[hg.x1], X[hg.x2], X[hg.x3], X[hg.x4]).value;
    hg.k = settings_.flexion_scale * D * (X[e[0]] - X[e[1]]).squaredNorm() / (ef.area / 3.0);
    hinges_.push_back(hg);
    ++flexion_;
  }
}

void MassSpringModel::add_hinge_forces(const Vec3Array& x, Vec3Array& f) const {
  for (const Hinge& hg : hinges_) {
    const auto c = constraints::dihedral_angle(x[hg.x1], x[hg.x2], x[hg.x3], x[hg.x4]);
    const double turn = std::remainder(c.value - hg.theta0, 2.0 * M_PI);
    const std::array<Index, 4> nodes = {hg.x1, hg.x2, hg.x3, hg.x4};
    for (int a = 0; a < 4; ++a) f[nodes[a]] -= (hg.k * turn) * c.grad[a];
  }
}

void MassSpringModel::add_hinge_rows(std::vector<double>& k_rows) const {
  // Gershgorin row sums of the hinges' stiffness k_b g g^T at rest.
  const Vec3Array& X = problem_.discretization().rest_positions();
  for (const Hinge& hg : hinges_) {
    const auto c = constraints::dihedral_angle(X[hg.x1], X[hg.x2], X[hg.x3], X[hg.x4]);
    double sum = 0.0;
    for (const Vec3& g : c.grad) sum += g.norm();
    const std::array<Index, 4> nodes = {hg.x1, hg.x2, hg.x3, hg.x4};
    for (int a = 0; a < 4; ++a) k_rows[nodes[a]] += hg.k * c.grad[a].norm() * sum;
  }
}

void MassSpringModel::build_map() {
  const Discretization& disc = problem_.discretization();
  const Vec3Array& X = disc.rest_positions();
  std::vector<Index> surface;
  Vec3Array Xs;
  for (Index i = 0; i < disc.num_nodes(); ++i)
    if (on_surface_[i]) surface.push_back(i), Xs.push_back(X[i]);
  const double spacing = disc.mean_spacing();
  const SpatialGrid grid(Xs, 2.0 * spacing);
  const std::size_t k = std::min(static_cast<std::size_t>(settings_.map_neighbours), Xs.size());
  map_start_.push_back(0);
  for (Index i = 0; i < disc.num_nodes(); ++i) {
    if (on_surface_[i]) continue;
    std::vector<std::pair<double, Index>> near;
    for (double r = 2.0 * spacing; near.size() < k; r *= 1.5) {
      near.clear();
      grid.for_each_within(X[i], r, [&](Index j, double d) { near.emplace_back(d, surface[j]); });
    }
    std::partial_sort(near.begin(), near.begin() + static_cast<long>(k), near.end());
    double sum = 0.0;
    for (std::size_t a = 0; a < k; ++a) sum += 1.0 / near[a].first;
    for (std::size_t a = 0; a < k; ++a) {
      map_node_.push_back(near[a].second);
      map_weight_.push_back(1.0 / near[a].first / sum);
    }
    inner_.push_back(i);
    map_start_.push_back(static_cast<Index>(map_node_.size()));
  }
}

void MassSpringModel::map_inner(double s) {
  const Vec3Array& X = problem_.discretization().rest_positions();
  for (std::size_t r = 0; r < inner_.size(); ++r) {
    const Index i = inner_[r];
    if (problem_.constrained()[i]) {
      x_[i] = problem_.prescribed_position(i, s);
      continue;
    }
    Vec3 u = Vec3::Zero();
    for (Index e = map_start_[r]; e < map_start_[r + 1]; ++e)
      u += map_weight_[e] * (x_[map_node_[e]] - X[map_node_[e]]);
    x_[i] = X[i] + u;
  }
}

StepReport MassSpringModel::frame(double s_prev, double s_next) {
  const Index n = static_cast<Index>(x_.size());
  const auto& fixed = problem_.constrained();
  std::fill(f_int_.begin(), f_int_.end(), Vec3::Zero());
  reset_loads();
  const double w = 1.0 / substeps_, decay = std::exp(-settings_.damping_per_s * dt_);
  Vec3Array x_old(x_.size());
  for (int j = 1; j <= substeps_; ++j) {
    const double s = s_prev + (s_next - s_prev) * j * w;
    problem_.external_forces(s, f_ext_);
    // Loads on the inner nodes go to the surface nodes they follow (the transpose of the map).
    for (std::size_t r = 0; r < inner_.size(); ++r)
      for (Index e = map_start_[r]; e < map_start_[r + 1]; ++e)
        f_ext_[map_node_[e]] += map_weight_[e] * f_ext_[inner_[r]];
    std::fill(f_.begin(), f_.end(), Vec3::Zero());
    springs_.add_forces(x_, v_, f_);
    add_hinge_forces(x_, f_);
    for (Index i = 0; i < n; ++i) {
      f_int_[i] += w * f_[i];
      x_old[i] = x_[i];
      if (!on_surface_[i]) continue;
      if (fixed[i]) {
        x_[i] = problem_.prescribed_position(i, s);
        v_[i] = (x_[i] - x_old[i]) / dt_;
        continue;
      }
      v_[i] = decay * (v_[i] + (dt_ / mass_[i]) * (f_[i] + f_ext_[i]));
      x_[i] += dt_ * v_[i];
    }
    project_tool_contacts(x_, mass_, dt_, s, w);
    for (Index i = 0; i < n; ++i)
      if (on_surface_[i] && !fixed[i]) v_[i] = (x_[i] - x_old[i]) / dt_;
  }
  map_inner(s_next);
  StepReport r;
  r.iterations = substeps_;
  return r;
}

double MassSpringModel::total_mass() const {
  double m = 0.0;
  for (double mi : mass_) m += mi;
  return m;
}

nlohmann::json MassSpringModel::method_info() const {
  return {{"method", "surface mass-spring with flexion springs, semi-implicit Euler (Li et al. 2018, [8])"},
          {"surface_nodes", std::count(on_surface_.begin(), on_surface_.end(), 1)},
          {"shell_thickness_m", thickness_},
          {"structural_springs", structural_},
          {"flexion_hinges", flexion_},
          {"flexion_scale", settings_.flexion_scale},
          {"damping_ratio", settings_.damping_ratio},
          {"damping_per_s", settings_.damping_per_s},
          {"substep_s", dt_},
          {"substeps_per_frame", substeps_},
          {"time_step_safety", settings_.time_step_safety},
          {"inner_nodes_mapped", inner_.size()},
          {"map_neighbours", settings_.map_neighbours}};
}

}  // namespace vascsim
