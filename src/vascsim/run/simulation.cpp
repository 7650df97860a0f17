#include "vascsim/run/simulation.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cmath>
#include <numbers>

#include "vascsim/core/beam_theory.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/geometry/vertex_normals.hpp"
#include "vascsim/model/inversion_check.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/body_builder.hpp"
#include "vascsim/run/contact_surface_builder.hpp"
#include "vascsim/run/discretization_setup.hpp"
#include "vascsim/run/region_builder.hpp"

namespace vascsim {

Simulation::Simulation(const Scene& scene, const BuildChecks& checks) : scene_(scene) {
  try {
    build(checks);
  } catch (const InputError& e) {
    // Errors found while assembling (overlapping regions, no supports, ...) name the scene file too.
    const std::string msg = e.what();
    if (msg.rfind(scene.file, 0) == 0) throw;
    throw InputError(scene.file + ": " + msg);
  }
}

void Simulation::build(const BuildChecks& checks) {
  const Scene& scene = scene_;
  const auto t0 = SteadyClock::now();
  body_ = std::make_unique<Body>(build_body(scene.geometry));
  const NodeCloud& cloud = body_->cloud;
  spdlog::info("geometry: {} with {} nodes and {} virtual tetrahedra", cloud.kind, cloud.positions.size(),
               cloud.tets.size());
  if (checks.after_body) checks.after_body(*body_);
  disc_ = std::make_unique<Discretization>(cloud, scene.material, discretization_options(scene, *body_));
  spdlog::info(
      "discretization: mean spacing {:.4g} m, mean neighbours {:.1f}, volume {:.4g} m^3 (tets {:.4g} m^3)",
      disc_->mean_spacing(), disc_->mean_neighbours(), disc_->total_volume(), disc_->tet_volume());
  EnergyOptions energy = scene.energy;
  if (energy.law && energy.law->needs_frame()) energy.frames = wall_frames(*body_, scene);
  energy_ = std::make_unique<PointPrimitiveEnergy>(*disc_, energy);
  problem_ = std::make_unique<Problem>(*energy_, build_regions(scene, *disc_, *body_), scene.gravity_m_s2,
                                       scene.obstacles);
  if (scene.contact.embedded) {
    ContactSurfaceReport& r = contact_report_.emplace();
    problem_->set_contact_surface(build_contact_surface(scene, *body_, *disc_, r));
    spdlog::info(
        "contact: the tools meet the wall's surface at {} samples {:.3g} m apart ({} interpolating their "
        "triangle's nodes, {} on the quadratic fit, the others on the MLS map) and {} nodes below it, "
        "stiffness {:.3g} Pa/m",
        r.samples, r.spacing_m, r.interpolated, r.quadratic, r.node_samples, r.stiffness_pa_per_m);
  }
  selections_ = describe_selections(scene, *disc_, *body_, problem_->regions());
  for (const RegionSelection& r : selections_)
    for (const std::string& w : r.warnings) spdlog::warn("{}", w);
  for (const auto& p : scene.probes) {
    Index best = 0;
    double bd = INFINITY;
    for (Index i = 0; i < disc_->num_nodes(); ++i) {
      const double d = (disc_->rest_positions()[i] - p.position_m).squaredNorm();
      if (d < bd) bd = d, best = i;
    }
    probe_nodes_.push_back(best);
  }
  for (const auto& o : scene.obstacles)
    if (!scene.contact.embedded && o.radius_m + o.node_radius_m < 2.0 * disc_->mean_spacing())
      spdlog::warn(
          "obstacle '{}': radius {:.3g} m + node_radius_m {:.3g} m is below 2 node spacings ({:.3g} m): the "
          "tool may slip between nodes; set node_radius_m to about half the spacing (docs/haptics.md)",
          o.name, o.radius_m, o.node_radius_m, 2.0 * disc_->mean_spacing());
  check_motion_sizes();
  if (problem_->num_constrained() == disc_->num_nodes()) {
    std::string held;
    for (const Region& r : problem_->regions())
      if (r.bc == RegionBcType::Fixed || r.bc == RegionBcType::Displacement)
        held += fmt::format("{}'{}'", held.empty() ? "" : ", ", r.name);
    throw InputError(fmt::format(
        "key 'regions': the fixed and displacement regions ({}) hold all {} nodes, so nothing is left to "
        "deform; narrow their 'select' to the supports",
        held, disc_->num_nodes()));
  }
  model_ = make_model(scene.model, *problem_, scene.own_model_settings());
  setup_s_ = seconds_since(t0);
}

// A prescribed displacement or a tool motion longer than the body's bounding-box diagonal is a mistake in the
// input (a unit slip: 10 m for 10 mm), not a load any model can follow.
void Simulation::check_motion_sizes() const {
  const Vec3Array& X = disc_->rest_positions();
  Vec3 lo = X.front(), hi = X.front();
  for (const Vec3& p : X) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double size = (hi - lo).norm();
  const auto check = [&](const std::string& key, double length) {
    if (length > size)
      throw InputError(
          fmt::format("{}: key '{}': a motion of {:.4g} m is larger than the body (its bounding box "
                      "diagonal is {:.4g} m); lengths are in metres",
                      scene_.file, key, length, size));
  };
  for (std::size_t r = 0; r < scene_.regions.size(); ++r) {
    const RegionSpec& region = scene_.regions[r];
    if (region.bc == RegionBcType::Displacement)
      check(fmt::format("regions.{}.bc.{}", r, region.has_vector ? "vector_m" : "magnitude_m"),
            region.has_vector ? region.vector.norm() : std::abs(region.magnitude));
  }
  for (std::size_t o = 0; o < scene_.obstacles.size(); ++o)
    check(fmt::format("obstacles.{}.motion_m", o), scene_.obstacles[o].motion_m.norm());
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
  const std::vector<ObstacleLoad> loads = step > 0 ? model_->obstacle_loads() : std::vector<ObstacleLoad>{};
  for (std::size_t o = 0; o < scene_.obstacles.size(); ++o) {
    const RigidObstacle& ob = scene_.obstacles[o];
    ObstacleMeasure m;
    const double travel = ob.motion_m.norm();
    m.displacement_m = report.load_factor * travel;
    if (o < loads.size()) {
      m.force_vector_n = loads[o].force_vector_n;
      m.torque_vector_n_m = loads[o].torque_vector_n_m;
      m.contacts = loads[o].contacts;
    }
    m.force_n = travel > 0.0 ? m.force_vector_n.dot(ob.motion_m / travel) : m.force_vector_n.norm();
    rec.obstacles.push_back(m);
  }
  for (std::size_t p = 0; p < probe_nodes_.size(); ++p) {
    const Vec3 u = x[probe_nodes_[p]] - disc_->rest_positions()[probe_nodes_[p]];
    const std::string& c = scene_.probes[p].component;
    rec.probes.push_back(c == "x" ? u.x() : c == "y" ? u.y() : c == "z" ? u.z() : u.norm());
  }
  return rec;
}

const MlsMap* Simulation::surface_map() {
  if (!surface_map_ && body_->surface) {
    const auto t0 = SteadyClock::now();
    surface_map_ =
        std::make_unique<MlsMap>(disc_->rest_positions(), body_->surface->rest_vertices, scene_.mapping);
    const MlsMapReport& r = surface_map_->report();
    spdlog::info(
        "surface map: {} vertices, |S| mean {:.1f} (min {}, max {}), max cond {:.3g}, {} vertices grown, "
        "{:.2f} s",
        surface_map_->num_vertices(), r.mean_support, r.min_support, r.max_support, r.max_cond,
        r.grown_vertices, seconds_since(t0));
  }
  return surface_map_.get();
}

SurfaceFrame Simulation::surface_frame() {
  const MlsMap* map = surface_map();
  if (!map)
    throw InputError(
        fmt::format("{}: geometry '{}' has no render surface", scene_.file, scene_.geometry.type));
  SurfaceFrame f;
  const Vec3Array& x = model_->positions();
  const Vec3Array& X = disc_->rest_positions();
  Vec3Array u(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) u[i] = x[i] - X[i];
  map->map_displacements(u, f.displacements);
  f.positions.resize(f.displacements.size());
  for (std::size_t v = 0; v < f.positions.size(); ++v)
    f.positions[v] = map->rest_surface()[v] + f.displacements[v];
  vertex_normals(body_->surface->triangles, f.positions, f.normals);
  return f;
}

StepRecord Simulation::initial_record() const {
  return measure(0, StepReport{});
}

void Simulation::check_state(const std::string& where) {
  const InversionReport inversion = check_inversion(*problem_, model_->positions());
  if (!inversion.any()) return;
  // A rigid tool in frictionless contact projects nodes onto its surface: under its rim the node lattice can
  // fold locally (a press of the haptic test block by 0.8 mm folds 1-4 of its 5,184 virtual tetrahedra) while
  // the solution elsewhere holds. With tools the run goes on and counts such steps; without, it is a failure.
  if (!scene_.obstacles.empty()) {
    if (inverted_steps_++ == 0)
      spdlog::warn("{}: {}: {} (under a tool's contact; the run goes on, summary.json counts such steps)",
                   scene_.model, where, inversion.describe());
    return;
  }
  throw NumericalError(
      fmt::format("{}: {}: {}; the state is no longer physical: use smaller steps (load_steps, "
                  "step_s or frame_s) or a smaller load",
                  scene_.model, where, inversion.describe()));
}

StepRecord Simulation::advance(int k) {
  const auto t0 = SteadyClock::now();
  const StepReport rep = model_->advance(k);
  check_state(fmt::format("step {} (t = {:.6g} s, load factor {:.4g})", k, rep.time_s, rep.load_factor));
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
