#include "vascsim/scene/simulation.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>
#include <spdlog/spdlog.h>

#include "vascsim/core/error.hpp"
#include "vascsim/core/beam_theory.hpp"
#include "vascsim/geometry/boundary.hpp"
#include "vascsim/geometry/mesh_wall.hpp"
#include "vascsim/io/mesh_import.hpp"
#include "vascsim/geometry/swept_vessel.hpp"
#include "vascsim/geometry/vertex_normals.hpp"
#include "vascsim/model/registry.hpp"

namespace vascsim {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double patch_center_s(const SelectorSpec& s, const WallCoordinates& wall) {
  return s.s_center_fraction >= 0.0 ? s.s_center_fraction * wall.length_m : s.s_center_m;
}

std::vector<char> select_nodes(const SelectorSpec& s, const RegionSpec& reg, const Scene& scene,
                               const Discretization& disc, const Body& body) {
  const Vec3Array& X = disc.rest_positions();
  const auto& wall = body.wall;
  const double tol = 1e-6 * disc.mean_spacing();
  std::vector<char> in(X.size(), 0);
  const bool needs_wall = s.type == "cylinder_end" || s.type == "wall_patch" || s.type == "surface_patch";
  const bool needs_line = s.type == "cylinder_end" || s.type == "wall_patch";
  if (needs_wall && !wall)
    throw InputError(fmt::format("{}: region '{}': selector '{}' needs a vessel geometry (tube, vessel or mesh)",
                                 scene.file, reg.name, s.type));
  if (needs_line && !wall->has_centerline())
    throw InputError(fmt::format("{}: region '{}': selector '{}' needs a centre-line (tube or vessel geometry); "
                                 "use surface_patch or box on an imported mesh",
                                 scene.file, reg.name, s.type));
  for (std::size_t i = 0; i < X.size(); ++i) {
    const Vec3& p = X[i];
    const Index n = static_cast<Index>(i);
    bool hit = false;
    if (s.type == "all") {
      hit = true;
    } else if (s.type == "box") {
      hit = (p.array() >= s.min_m.array() - tol).all() && (p.array() <= s.max_m.array() + tol).all();
    } else if (s.type == "cylinder_end") {
      hit = s.end == "start" ? wall->s_m[i] <= s.depth_m + tol : wall->s_m[i] >= wall->length_m - s.depth_m - tol;
    } else {
      const bool on_surface = s.surface == "outer" ? wall->on_outer(n) : wall->on_inner(n);
      if (s.type == "wall_patch") {
        const double s_center = patch_center_s(s, *wall);
        const double dtheta = std::remainder(wall->theta_deg[i] - s.angle_center_deg, 360.0);
        hit = on_surface && std::abs(dtheta) <= s.angle_half_width_deg + 1e-9 &&
              std::abs(wall->s_m[i] - s_center) <= s.s_half_length_m + tol;
      } else {  // surface_patch
        hit = on_surface && (p - s.centre_m).norm() <= s.radius_m + tol;
      }
    }
    in[i] = hit ? 1 : 0;
  }
  return in;
}

// The "inward" direction of a patch: into the wall at the patch centre (wall_patch: minus the radial
// direction of the centre-line frame; surface_patch: minus the mean outward normal of its nodes).
Vec3 inward_direction(const SelectorSpec& s, const WallCoordinates& wall, const std::vector<Index>& nodes) {
  if (s.type == "wall_patch") return -wall.radial(patch_center_s(s, wall), s.angle_center_deg);
  Vec3 sum = Vec3::Zero();
  for (Index i : nodes) sum += wall.outward[static_cast<std::size_t>(i)];
  return -sum.normalized();
}

Body body_from_mesh(const MeshGeometrySpec& spec) {
  const TriangleMesh mesh = import_triangle_mesh(spec.file, spec.units_m);
  MeshWallSpec ws;
  ws.kind = spec.kind;
  ws.wall_thickness_m = spec.wall_thickness_m;
  ws.node_spacing_m = spec.node_spacing_m;
  ws.min_layers = spec.min_layers;
  ws.source = spec.file;
  return body_from_mesh_wall(make_mesh_wall(mesh, ws));
}

}  // namespace

Body build_body(const GeometrySpec& spec) {
  if (spec.type == "tube") {
    SweptVesselSpec ss{spec.tube.outer_radius_m, spec.tube.wall_thickness_m, spec.tube.node_spacing_m,
                       std::max(3, spec.tube.min_layers)};
    return body_from_tube(make_tube(spec.tube), make_swept_vessel(straight_centerline(spec.tube.length_m), ss));
  }
  if (spec.type == "vessel") {
    const CenterlineSpec& c = spec.centerline;
    auto line = std::make_shared<const Centerline>(
        c.type == "straight" ? straight_centerline(c.length_m)
        : c.type == "bent"   ? bent_centerline(c.radius_of_curvature_m, c.angle_deg, c.leg_length_m)
        : c.type == "s"      ? s_centerline(c.radius_of_curvature_m, c.angle_deg, c.leg_length_m)
                             : Centerline(c.points_m));
    SweptVesselSpec ss{spec.tube.outer_radius_m, spec.tube.wall_thickness_m, spec.tube.node_spacing_m,
                       spec.tube.min_layers};
    return body_from_swept_vessel(make_swept_vessel(*line, ss), line);
  }
  if (spec.type == "mesh") return body_from_mesh(spec.mesh);
  NodeCloud c = make_box(spec.box);
  if (spec.type == "beam") c.kind = "beam";
  return body_from_lattice(std::move(c));
}

NodeCloud build_geometry(const GeometrySpec& spec) { return build_body(spec).cloud; }

std::vector<Region> build_regions(const Scene& scene, const Discretization& disc, const Body& body) {
  std::vector<Region> out;
  const auto faces = boundary_faces(disc.tets());
  for (const RegionSpec& rs : scene.regions) {
    Region r;
    r.name = rs.name;
    r.bc = rs.bc;
    const std::vector<char> in = select_nodes(rs.select, rs, scene, disc, body);
    for (std::size_t i = 0; i < in.size(); ++i)
      if (in[i]) r.nodes.push_back(static_cast<Index>(i));
    if (r.nodes.empty())
      throw InputError(fmt::format("{}: key 'regions.{}.select': region '{}' selects no nodes", scene.file,
                                   &rs - scene.regions.data(), rs.name));
    const Vec3 dir = rs.direction_inward ? inward_direction(rs.select, *body.wall, r.nodes) : rs.direction;
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

std::vector<materials::MaterialFrame> wall_frames(const Body& body, const Scene& scene) {
  if (!body.wall || !body.wall->has_centerline())
    throw InputError(fmt::format("{}: key 'material.law': '{}' takes its fibre directions from the vessel's "
                                 "centre-line; geometry '{}' has none (use a tube or a vessel)",
                                 scene.file, scene.material_law, scene.geometry.type));
  const WallCoordinates& w = *body.wall;
  std::vector<materials::MaterialFrame> frames(body.cloud.positions.size());
  for (std::size_t i = 0; i < frames.size(); ++i)
    frames[i] = materials::make_material_frame(w.centerline->tangent(w.s_m[i]), w.outward[i]);
  return frames;
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
  body_ = std::make_unique<Body>(build_body(scene.geometry));
  const NodeCloud& cloud = body_->cloud;
  spdlog::info("geometry: {} with {} nodes and {} virtual tetrahedra", cloud.kind, cloud.positions.size(),
               cloud.tets.size());
  disc_ = std::make_unique<Discretization>(cloud, scene.material, scene.discretization);
  spdlog::info("discretization: mean spacing {:.4g} m, mean neighbours {:.1f}, volume {:.4g} m^3 (tets {:.4g} m^3)",
               disc_->mean_spacing(), disc_->mean_neighbours(), disc_->total_volume(), disc_->tet_volume());
  EnergyOptions energy = scene.energy;
  if (energy.law && scene.model == "paper_literal")
    throw InputError(fmt::format("{}: key 'material.law': the paper_literal model is the paper's SVK; '{}' needs "
                                 "quasi_static, explicit or xpbd",
                                 scene.file, scene.material_law));
  if (energy.law && scene.model == "xpbd" && scene.xpbd.elastic != XpbdElastic::MeshlessStrain)
    throw InputError(fmt::format("{}: key 'material.law': with xpbd, '{}' needs xpbd.elastic = meshless_strain (the "
                                 "tet option is its own neo-Hookean)",
                                 scene.file, scene.material_law));
  if (energy.law && energy.law->needs_frame()) energy.frames = wall_frames(*body_, scene);
  energy_ = std::make_unique<PointPrimitiveEnergy>(*disc_, energy);
  problem_ = std::make_unique<Problem>(*energy_, build_regions(scene, *disc_, *body_), scene.gravity_m_s2);
  for (const auto& p : scene.probes) {
    Index best = 0;
    double bd = INFINITY;
    for (Index i = 0; i < disc_->num_nodes(); ++i) {
      const double d = (disc_->rest_positions()[i] - p.position_m).squaredNorm();
      if (d < bd) bd = d, best = i;
    }
    probe_nodes_.push_back(best);
  }
  if (!scene.obstacles.empty() && scene.model != "xpbd" && scene.model != "quasi_static")
    throw InputError(fmt::format("{}: key 'obstacles': rigid obstacles are supported by the xpbd and quasi_static "
                                 "models only (model is '{}')",
                                 scene.file, scene.model));
  for (const auto& o : scene.obstacles)
    if (o.radius_m + o.node_radius_m < 2.0 * disc_->mean_spacing())
      spdlog::warn("obstacle '{}': radius {:.3g} m + node_radius_m {:.3g} m is below 2 node spacings ({:.3g} m): the "
                   "tool may slip between nodes; set node_radius_m to about half the spacing (docs/haptics.md)",
                   o.name, o.radius_m, o.node_radius_m, 2.0 * disc_->mean_spacing());
  ModelSettings settings{scene.explicit_settings, scene.quasi_static, scene.xpbd, scene.paper_literal};
  settings.xpbd.obstacles = scene.obstacles;
  settings.quasi_static.obstacles = scene.obstacles;
  model_ = make_model(scene.model, *problem_, settings);
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
  const std::vector<ObstacleLoad> loads = step > 0 ? model_->obstacle_loads() : std::vector<ObstacleLoad>{};
  for (std::size_t o = 0; o < scene_.obstacles.size(); ++o) {
    const RigidObstacle& ob = scene_.obstacles[o];
    ObstacleMeasure m;
    const double travel = ob.motion_m.norm();
    m.displacement_m = report.load_factor * travel;
    if (o < loads.size()) {
      m.force_n = loads[o].force_n;
      m.torque_n_m = loads[o].torque_n_m;
      m.contacts = loads[o].contacts;
    }
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

const MlsMap* Simulation::surface_map() {
  if (!surface_map_ && body_->surface) {
    const auto t0 = std::chrono::steady_clock::now();
    surface_map_ = std::make_unique<MlsMap>(disc_->rest_positions(), body_->surface->rest_vertices, scene_.mapping);
    const MlsMapReport& r = surface_map_->report();
    spdlog::info("surface map: {} vertices, |S| mean {:.1f} (min {}, max {}), max cond {:.3g}, {} vertices grown, {:.2f} s",
                 surface_map_->num_vertices(), r.mean_support, r.min_support, r.max_support, r.max_cond,
                 r.grown_vertices, seconds_since(t0));
  }
  return surface_map_.get();
}

SurfaceFrame Simulation::surface_frame() {
  const MlsMap* map = surface_map();
  if (!map) throw InputError(fmt::format("{}: geometry '{}' has no render surface", scene_.file, scene_.geometry.type));
  SurfaceFrame f;
  const Vec3Array& x = model_->positions();
  const Vec3Array& X = disc_->rest_positions();
  Vec3Array u(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) u[i] = x[i] - X[i];
  map->map_displacements(u, f.displacements);
  f.positions.resize(f.displacements.size());
  for (std::size_t v = 0; v < f.positions.size(); ++v) f.positions[v] = map->rest_surface()[v] + f.displacements[v];
  vertex_normals(body_->surface->triangles, f.positions, f.normals);
  return f;
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
