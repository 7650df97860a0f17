#include "vascsim/run/runner.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <numeric>

#include "vascsim/core/error.hpp"
#include "vascsim/core/interrupt.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/model/integration_constraint.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/output_writer.hpp"
#include "vascsim/run/run_findings.hpp"
#include "vascsim/run/tool_reach.hpp"
#include "vascsim/run/tool_series.hpp"

namespace vascsim {

namespace {

// Prints -0 as 0.
double clean(double x) {
  return x == 0.0 ? 0.0 : x;
}

std::string csv_row(const StepRecord& r) {
  std::string s = fmt::format("{},{:.9g},{:.9g}", r.step, r.report.time_s, r.report.load_factor);
  for (const auto& m : r.regions)
    s += fmt::format(",{:.9g},{:.9g}", clean(m.displacement_m), clean(m.force_n));
  for (double p : r.probes) s += fmt::format(",{:.9g}", clean(p));
  for (const auto& m : r.obstacles)
    s += fmt::format(",{:.9g},{:.9g}", clean(m.displacement_m), clean(m.force_n));
  s += fmt::format(",{},{},{:.3g},{}", r.report.iterations, r.report.inner_iterations, r.report.residual,
                   r.report.converged ? 1 : 0);
  return s;
}

nlohmann::json step_json(const Scene& scene, const StepRecord& r) {
  nlohmann::json regions = nlohmann::json::object();
  for (std::size_t i = 0; i < r.regions.size(); ++i)
    regions[scene.regions[i].name] = {{"displacement_m", r.regions[i].displacement_m},
                                      {"force_n", r.regions[i].force_n},
                                      {"force_vector_n",
                                       {r.regions[i].force_vector_n.x(), r.regions[i].force_vector_n.y(),
                                        r.regions[i].force_vector_n.z()}}};
  nlohmann::json probes = nlohmann::json::object();
  for (std::size_t i = 0; i < r.probes.size(); ++i)
    probes[scene.probes[i].name + "_displacement_m"] = r.probes[i];
  for (std::size_t i = 0; i < r.obstacles.size(); ++i)
    regions[scene.obstacles[i].name] = {
        {"displacement_m", r.obstacles[i].displacement_m},
        {"force_n", r.obstacles[i].force_n},
        {"force_vector_n",
         {r.obstacles[i].force_vector_n.x(), r.obstacles[i].force_vector_n.y(),
          r.obstacles[i].force_vector_n.z()}},
        {"torque_vector_n_m",
         {r.obstacles[i].torque_vector_n_m.x(), r.obstacles[i].torque_vector_n_m.y(),
          r.obstacles[i].torque_vector_n_m.z()}},
        {"contacts", r.obstacles[i].contacts}};
  return {{"step", r.step},
          {"time_s", r.report.time_s},
          {"load_factor", r.report.load_factor},
          {"iterations", r.report.iterations},
          {"inner_iterations", r.report.inner_iterations},
          {"residual", r.report.residual},
          {"converged", r.report.converged},
          {"wall_s", r.wall_s},
          {"regions", regions},
          {"probes", probes}};
}

// What each region selected beside what was asked (the warnings were logged when the simulation was built).
nlohmann::json region_reports(const Simulation& sim) {
  nlohmann::json out = nlohmann::json::array();
  for (const RegionSelection& r : sim.region_selections()) out.push_back(r.report);
  return out;
}

}  // namespace

std::vector<std::string> probe_columns(const Scene& scene) {
  std::vector<std::string> c = {"step", "time_s", "load_factor"};
  for (const auto& r : scene.regions) {
    c.push_back(r.name + "_displacement_m");
    c.push_back(r.name + "_force_n");
  }
  for (const auto& p : scene.probes) c.push_back(p.name + "_displacement_m");
  for (const auto& o : scene.obstacles) {
    c.push_back(o.name + "_displacement_m");
    c.push_back(o.name + "_force_n");
  }
  for (const char* s : {"iterations", "inner_iterations", "residual", "converged"}) c.emplace_back(s);
  return c;
}

// Where the tools meet the tissue: "nodes", or the embedded contact's surface (contact.surface).
static nlohmann::json contact_info(const Simulation& sim) {
  const auto& r = sim.contact_surface_report();
  if (!r) return {{"surface", "nodes"}};
  return {{"surface", "embedded"},
          {"shape_functions", shape_functions_name(sim.scene().contact.shape_functions)},
          {"samples", r->samples},
          {"interpolated_samples", r->interpolated},
          {"quadratic_samples", r->quadratic},
          {"node_samples", r->node_samples},
          {"sample_spacing_m", r->spacing_m},
          {"sample_spacing_min_m", r->spacing_min_m},
          {"stiffness_pa_per_m", r->stiffness_pa_per_m}};
}

// How far the quadrature is from the discrete divergence theorem inside the body
// (model/integration_constraint).
static nlohmann::json integration_constraint_info(const Discretization& disc) {
  const IntegrationConstraintReport r = integration_constraint_report(disc);
  return {{"interior_nodes", r.interior_nodes},
          {"interior_max", r.interior_max},
          {"interior_rms", r.interior_rms}};
}

nlohmann::json describe_run(const Scene& scene, Simulation& sim) {
  const auto& disc = sim.discretization();
  const nlohmann::json wall_stretch =
      disc.wall_stretch() > 0.0 ? nlohmann::json(disc.wall_stretch()) : nlohmann::json();
  return {
      {"scene", scene.name},
      {"scene_file", scene.file},
      {"model", sim.model().name()},
      {"parameters", scene.resolved},
      {"nodes", disc.num_nodes()},
      {"virtual_tetrahedra", disc.tets().size()},
      {"neighbour_pairs", disc.pairs().col.size()},
      {"mean_neighbours", disc.mean_neighbours()},
      {"mean_spacing_m", disc.mean_spacing()},
      {"support_radius_min_m", *std::min_element(disc.support_radius().begin(), disc.support_radius().end())},
      {"support_radius_max_m", *std::max_element(disc.support_radius().begin(), disc.support_radius().end())},
      {"nodes_with_grown_support", disc.grown_nodes()},
      {"support_wall_stretch", wall_stretch},
      {"support_wall_across_scale",
       disc.wall_stretch() > 0.0 ? nlohmann::json(disc.wall_across_scale()) : nlohmann::json()},
      {"energy_points_per_node", disc.energy_points()},
      {"integration_constraint", integration_constraint_info(disc)},
      {"volume_m3", disc.total_volume()},
      {"mass_kg", std::accumulate(disc.masses().begin(), disc.masses().end(), 0.0)},
      {"solver", sim.model().info()},
      {"threads", omp_get_max_threads()},
      {"contact", contact_info(sim)},
      {"regions", region_reports(sim)}};
}

nlohmann::json surface_map_info(Simulation& sim) {
  const MlsMapReport& r = sim.surface_map()->report();
  return {{"vertices", sim.surface_map()->num_vertices()},
          {"triangles", sim.body().surface->triangles.size()},
          {"mean_support", r.mean_support},
          {"min_support", r.min_support},
          {"max_support", r.max_support},
          {"max_cond", r.max_cond},
          {"grown_vertices", r.grown_vertices},
          {"base_radius_m", r.base_radius_m},
          {"max_radius_m", r.max_radius_m}};
}

std::unique_ptr<Simulation> build_run(const Scene& scene, const BuildChecks& checks) {
  auto sim = std::make_unique<Simulation>(scene, checks);
  const bool surface = scene.output.surface && sim->body().surface.has_value();
  if (scene.output.surface && !surface)
    throw InputError(fmt::format("{}: key 'output.surface': geometry '{}' has no render surface", scene.file,
                                 scene.geometry.type));
  if (surface) sim->surface_map();  // its guard fails here, before the first step
  return sim;
}

namespace {

// Before the first step: the tools whose motion never reaches the body, one warning each (also logged).
std::vector<std::string> tool_reach_warnings(const Scene& scene, const Simulation& sim) {
  std::vector<std::string> warnings;
  for (std::size_t o = 0; o < scene.obstacles.size(); ++o) {
    const ToolReach reach = tool_reach_by_load(scene.obstacles[o], sim.discretization().rest_positions());
    if (!reach.touches()) warnings.push_back(tool_reach_warning(reach, scene.obstacles[o], o));
  }
  for (const std::string& w : warnings) spdlog::warn("{}", w);
  return warnings;
}

}  // namespace

nlohmann::json run_scene(const Scene& scene, const RunOptions& options) {
  const OutputWriter out(options.out_dir);
  const Stopwatch total;
  const std::unique_ptr<Simulation> built = build_run(scene, options.checks);
  Simulation& sim = *built;
  Model& model = sim.model();
  if (options.after_setup) options.after_setup(sim);
  // The scene's own warnings first (`vascsim run` logged them with the model's accuracy warnings).
  std::vector<std::string> warnings = scene.warnings;
  for (std::string& w : tool_reach_warnings(scene, sim)) warnings.push_back(std::move(w));
  CsvTable probes = out.table("probes.csv", probe_columns(scene));

  const bool surface = scene.output.surface;
  const nlohmann::json surface_info = surface ? surface_map_info(sim) : nlohmann::json(nullptr);
  VtkSeries node_series = out.series("nodes"), surface_series = out.series("surface");
  ToolSeries tool_series(out, scene, surface);
  // Dynamic models' series are indexed by time, load-stepped ones by the load factor.
  const bool dynamic = find_model(scene.model).capabilities.dynamic;
  auto write_vtk = [&](const StepRecord& r) {
    if (!(scene.output.vtk || surface) || r.step % scene.output.vtk_every != 0) return;
    const double stamp = dynamic ? r.report.time_s : r.report.load_factor;
    if (scene.output.vtk)
      node_series.add_nodes(stamp, fmt::format("nodes_{:04d}.vtu", r.step),
                            sim.discretization().rest_positions(), model.positions(),
                            sim.discretization().tets());
    if (surface) {
      surface_series.add_surface(stamp, fmt::format("surface_{:04d}.vtu", r.step), sim.surface_frame(),
                                 *sim.body().surface);
      tool_series.add(stamp, fmt::format("tools_{:04d}.vtu", r.step), tools_at(scene, r.report.load_factor));
    }
  };

  nlohmann::json steps = nlohmann::json::array();
  RunFindings findings(scene, sim.body());
  auto record = [&](const StepRecord& r) {
    probes.add_row(csv_row(r));
    steps.push_back(step_json(scene, r));
    findings.add(r);
    write_vtk(r);
    if (options.on_step) options.on_step(r, model.num_steps());
  };
  StepRecord last = sim.initial_record();
  record(last);
  double solve_s = 0.0;
  int unconverged = 0;
  bool interrupted = false;
  for (int k = 1; k <= model.num_steps(); ++k) {
    // Ctrl-C: stop at this step boundary with every file complete up to the last step.
    if (interrupt_requested()) {
      interrupted = true;
      break;
    }
    last = sim.advance(k);
    solve_s += last.wall_s;
    unconverged += last.report.converged ? 0 : 1;
    record(last);
  }
  // Found after the last step, where `vascsim run` prints summary.json's warnings: logged as well, each was
  // printed twice.
  for (const std::string& w : findings.warnings(model.num_steps())) {
    spdlog::debug("{}", w);
    warnings.push_back(w);
  }

  nlohmann::json summary = describe_run(scene, sim);
  summary.update(
      {{"timings_s", {{"setup", sim.setup_seconds()}, {"solve", solve_s}, {"total", total.seconds()}}},
       {"unconverged_steps", unconverged},
       {"warnings", warnings},
       {"interrupted", interrupted},
       {"inverted_steps", sim.inverted_steps()},
       {"planned_steps", model.num_steps()},
       {"steps", steps},
       {"surface_map", surface_info},
       {"outputs",
        {{"probes_csv", "probes.csv"},
         {"vtk", scene.output.vtk ? node_series.pvd_relative() : ""},
         {"surface", surface ? surface_series.pvd_relative() : ""},
         {"tools", tool_series.pvd_relative()}}}});
  const auto ref = sim.reference(last);
  if (!ref.is_null()) summary["reference"] = ref;
  out.write_summary(summary);
  return summary;
}

}  // namespace vascsim
