#include "vascsim/scene/simulation.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>
#include <spdlog/spdlog.h>

#include "vascsim/core/error.hpp"
#include "vascsim/experiments/timoshenko.hpp"
#include "vascsim/geometry/boundary.hpp"
#include "vascsim/model/registry.hpp"

namespace vascsim {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<char> select_nodes(const SelectorSpec& s, const RegionSpec& reg, const Scene& scene,
                               const Discretization& disc) {
  const Vec3Array& X = disc.rest_positions();
  const auto& tube = disc.cloud().tube;
  const double tol = 1e-6 * disc.mean_spacing();
  std::vector<char> in(X.size(), 0);
  if ((s.type == "cylinder_end" || s.type == "wall_patch") && !tube)
    throw InputError(fmt::format("{}: region '{}': selector '{}' needs a tube geometry", scene.file, reg.name, s.type));
  for (std::size_t i = 0; i < X.size(); ++i) {
    const Vec3& p = X[i];
    bool hit = false;
    if (s.type == "all") {
      hit = true;
    } else if (s.type == "box") {
      hit = (p.array() >= s.min_m.array() - tol).all() && (p.array() <= s.max_m.array() + tol).all();
    } else if (s.type == "cylinder_end") {
      hit = s.end == "start" ? p.z() <= s.depth_m + tol : p.z() >= tube->length_m - s.depth_m - tol;
    } else if (s.type == "wall_patch") {
      const double r = std::hypot(p.x(), p.y());
      const double radial_step = (tube->outer_radius_m - tube->inner_radius_m) / (tube->radial_layers - 1);
      const double target = s.surface == "outer" ? tube->outer_radius_m : tube->inner_radius_m;
      double dtheta = std::atan2(p.y(), p.x()) * 180.0 / std::numbers::pi - s.angle_center_deg;
      dtheta = std::remainder(dtheta, 360.0);
      hit = std::abs(r - target) <= 0.01 * radial_step && std::abs(dtheta) <= s.angle_half_width_deg + 1e-9 &&
            std::abs(p.z() - s.z_center_m) <= s.z_half_length_m + tol;
    }
    in[i] = hit ? 1 : 0;
  }
  return in;
}

}  // namespace

NodeCloud build_geometry(const GeometrySpec& spec) {
  if (spec.type == "tube") return make_tube(spec.tube);
  NodeCloud c = make_box(spec.box);
  if (spec.type == "beam") c.kind = "beam";
  return c;
}

std::vector<Region> build_regions(const Scene& scene, const Discretization& disc) {
  std::vector<Region> out;
  const auto faces = boundary_faces(disc.tets());
  for (const RegionSpec& rs : scene.regions) {
    Region r;
    r.name = rs.name;
    r.bc = rs.bc;
    const std::vector<char> in = select_nodes(rs.select, rs, scene, disc);
    for (std::size_t i = 0; i < in.size(); ++i)
      if (in[i]) r.nodes.push_back(static_cast<Index>(i));
    if (r.nodes.empty())
      throw InputError(fmt::format("{}: key 'regions.{}.select': region '{}' selects no nodes", scene.file,
                                   &rs - scene.regions.data(), rs.name));
    Vec3 dir = rs.direction;
    if (rs.direction_inward) {
      const double th = rs.select.angle_center_deg * std::numbers::pi / 180.0;
      dir = -Vec3(std::cos(th), std::sin(th), 0.0);
    }
    r.direction = dir;
    r.release_time_s = rs.release_time_s;
    if (std::isfinite(r.release_time_s) && scene.model != "xpbd")
      throw InputError(fmt::format("{}: key 'regions.{}.bc.release_time_s': releasing a region is supported by the "
                                   "xpbd model only (model is '{}')",
                                   scene.file, &rs - scene.regions.data(), scene.model));
    const Vec3 vec = rs.has_vector ? rs.vector : Vec3(rs.magnitude * dir);
    if (r.bc == RegionBcType::Displacement) r.displacement_m = vec;
    if (r.bc == RegionBcType::Force) {
      r.force_n = vec;
      // Spread by the boundary area lying inside the region; regions without such area by volume.
      const auto area = lumped_boundary_area(disc.rest_positions(), faces, in);
      double total = 0.0;
      for (Index i : r.nodes) total += area[i];
      for (Index i : r.nodes) r.force_weights.push_back(total > 0.0 ? area[i] / total : disc.volumes()[i]);
      if (!(total > 0.0)) {
        double vt = 0.0;
        for (double w : r.force_weights) vt += w;
        for (double& w : r.force_weights) w /= vt;
      }
    }
    out.push_back(std::move(r));
  }
  return out;
}

Simulation::Simulation(const Scene& scene) : scene_(scene) {
  try {
    build();
  } catch (const InputError& e) {
    // Errors found while assembling (overlapping regions, no supports, ...) name the scene file too.
    const std::string msg = e.what();
    if (msg.rfind(scene.file, 0) == 0) throw;
    throw InputError(scene.file + ": " + msg);
  }
}

void Simulation::build() {
  const Scene& scene = scene_;
  const auto t0 = std::chrono::steady_clock::now();
  const NodeCloud cloud = build_geometry(scene.geometry);
  spdlog::info("geometry: {} with {} nodes and {} virtual tetrahedra", cloud.kind, cloud.positions.size(),
               cloud.tets.size());
  disc_ = std::make_unique<Discretization>(cloud, scene.material, scene.discretization);
  spdlog::info("discretization: mean spacing {:.4g} m, mean neighbours {:.1f}, volume {:.4g} m^3 (tets {:.4g} m^3)",
               disc_->mean_spacing(), disc_->mean_neighbours(), disc_->total_volume(), disc_->tet_volume());
  energy_ = std::make_unique<PointPrimitiveEnergy>(*disc_, scene.energy);
  problem_ = std::make_unique<Problem>(*energy_, build_regions(scene, *disc_), scene.gravity_m_s2);
  for (const auto& p : scene.probes) {
    Index best = 0;
    double bd = INFINITY;
    for (Index i = 0; i < disc_->num_nodes(); ++i) {
      const double d = (disc_->rest_positions()[i] - p.position_m).squaredNorm();
      if (d < bd) bd = d, best = i;
    }
    probe_nodes_.push_back(best);
  }
  if (!scene.xpbd.obstacles.empty() && scene.model != "xpbd")
    throw InputError(fmt::format("{}: key 'obstacles': rigid obstacles are supported by the xpbd model only (model "
                                 "is '{}')",
                                 scene.file, scene.model));
  model_ = make_model(scene.model, *problem_,
                      ModelSettings{scene.explicit_settings, scene.quasi_static, scene.xpbd, scene.paper_literal});
  setup_s_ = seconds_since(t0);
}

StepRecord Simulation::measure(int step, const StepReport& report) const {
  StepRecord rec;
  rec.step = step;
  rec.report = report;
  const Vec3Array& x = model_->positions();
  Vec3Array f_int, f_ext;
  if (const Vec3Array* fc = model_->constraint_forces(); fc && step > 0)
    f_int = *fc;
  else
    energy_->forces(x, f_int);
  problem_->external_forces(report.load_factor, f_ext);
  rec.regions = problem_->measure(report.load_factor, x, f_int, f_ext);
  const std::vector<Vec3> tool_forces = step > 0 ? model_->obstacle_forces() : std::vector<Vec3>{};
  for (std::size_t o = 0; o < scene_.xpbd.obstacles.size(); ++o) {
    const RigidObstacle& ob = scene_.xpbd.obstacles[o];
    ObstacleMeasure m;
    const double travel = ob.motion_m.norm();
    m.displacement_m = report.load_factor * travel;
    m.force_n = o < tool_forces.size() ? tool_forces[o] : Vec3::Zero();
    m.force_projected_n = travel > 0.0 ? m.force_n.dot(ob.motion_m / travel) : m.force_n.norm();
    rec.obstacles.push_back(m);
  }
  for (std::size_t p = 0; p < probe_nodes_.size(); ++p) {
    const Vec3 u = x[probe_nodes_[p]] - disc_->rest_positions()[probe_nodes_[p]];
    const std::string& c = scene_.probes[p].component;
    rec.probes.push_back(c == "x" ? u.x() : c == "y" ? u.y() : c == "z" ? u.z() : u.norm());
  }
  return rec;
}

StepRecord Simulation::initial_record() const { return measure(0, StepReport{}); }

StepRecord Simulation::advance(int k) {
  const auto t0 = std::chrono::steady_clock::now();
  const StepReport rep = model_->advance(k);
  StepRecord rec = measure(k, rep);
  rec.wall_s = seconds_since(t0);
  return rec;
}

nlohmann::json Simulation::reference(const StepRecord& last) const {
  if (scene_.reference.type != "timoshenko_cantilever") return nullptr;
  const auto& g = scene_.geometry;
  std::size_t r = 0;
  while (problem_->regions()[r].name != scene_.reference.region) ++r;
  const Region& reg = problem_->regions()[r];
  const double P = last.report.load_factor * reg.force_n.norm();
  // The section dimension along the load is the bending "height".
  const Vec3 d = reg.force_n.normalized().cwiseAbs();
  const double t = d.z() >= d.y() ? g.beam_height_m : g.beam_width_m;
  const double b = d.z() >= d.y() ? g.beam_width_m : g.beam_height_m;
  const double ref = timoshenko_tip_deflection(P, g.beam_length_m, b, t, scene_.material.youngs_modulus_pa,
                                               scene_.material.poisson_ratio);
  const double got = last.regions[r].displacement_m;
  return {{"type", "timoshenko_cantilever"},
          {"region", reg.name},
          {"load_n", P},
          {"tip_deflection_m", got},
          {"reference_deflection_m", ref},
          {"ratio", got / ref},
          {"formula", "delta_T = P L^3/(3 E I) + P L/(kappa G A), kappa = 10(1+nu)/(12+11nu)"}};
}

}  // namespace vascsim
