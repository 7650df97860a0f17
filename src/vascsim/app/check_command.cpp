// `vascsim check SCENE.json`: a dry run. Builds everything `run` builds, through the same code and with the
// same errors (geometry, discretisation with its neighbourhoods, the surface map, regions, tools, the model's
// set-up; a haptic session's device files and rig), solves nothing, and prints what the run will be: its
// size, memory, expected time on this machine, expected force accuracy at this resolution, what each region
// selected, and whether each tool will reach the tissue. --json FILE writes the same as a JSON document.

#include <fmt/format.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "vascsim/app/command.hpp"
#include "vascsim/app/run_limits.hpp"
#include "vascsim/core/atomic_file.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/memory_usage.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/experiments/run_assessment.hpp"
#include "vascsim/run/haptic_session_setup.hpp"
#include "vascsim/run/runner.hpp"
#include "vascsim/run/tool_reach.hpp"

namespace vascsim {

namespace {

struct CheckFlags {
  std::string scene, json;
  std::vector<std::string> sets;
  bool yes = false;
};

const char* bc_name(RegionBcType bc) {
  switch (bc) {
    case RegionBcType::Fixed:
      return "fixed";
    case RegionBcType::Displacement:
      return "displacement";
    case RegionBcType::Force:
      return "force";
    case RegionBcType::Probe:
      return "probe";
  }
  return "?";
}

std::string mib(double bytes) {
  return fmt::format("{:.0f} MiB", bytes / (1024.0 * 1024.0));
}

// What a run of the scene builds, built the way the run builds it.
struct Built {
  std::unique_ptr<SessionSetup> session;
  std::unique_ptr<Simulation> headless;
  Simulation* sim = nullptr;
  double steps = 0.0;  // model steps the run takes
  std::vector<ToolReach> reach;
};

Built build(const Scene& scene, bool yes) {
  Built b;
  if (scene.haptics.enabled) {
    HapticRunOptions options;
    options.checks = node_limit(scene, yes);
    b.session = std::make_unique<SessionSetup>(scene, options);
    b.sim = &b.session->simulation();
    if (scene.output.surface && b.sim->body().surface) b.sim->surface_map();
    b.steps = b.session->frames();
    const SessionInputs& in = b.session->inputs();
    b.reach.push_back(tool_reach_on_trajectory(scene.obstacles[in.tool], in.trajectory, in.duration_s,
                                               b.sim->discretization().rest_positions()));
    return b;
  }
  b.headless = build_run(scene, node_limit(scene, yes));
  b.sim = b.headless.get();
  const CostCalibration* calibration = bundled_cost_calibration();
  b.steps = headless_model_steps(scene, *b.sim, calibration ? calibration->find(scene.model) : nullptr);
  for (const RigidObstacle& o : scene.obstacles)
    b.reach.push_back(tool_reach_by_load(o, b.sim->discretization().rest_positions()));
  return b;
}

nlohmann::json memory_report(Simulation& sim, const std::optional<CostEstimate>& cost) {
  nlohmann::json m = {{"resident_after_build_bytes", resident_bytes()},
                      {"peak_during_build_bytes", peak_resident_bytes()}};
  const nlohmann::json info = sim.model().info();
  if (info.contains("preconditioner") && info["preconditioner"].is_object() &&
      info["preconditioner"].contains("nnz_l"))
    m["factor_bytes"] = 8.0 * info["preconditioner"]["nnz_l"].get<double>();  // double entries of L
  if (cost) m["expected_run_peak"] = {{"bytes", cost->peak_bytes}, {"factor", cost->memory_factor}};
  return m;
}

nlohmann::json tools_report(const Scene& scene, const std::vector<ToolReach>& reach) {
  nlohmann::json tools = nlohmann::json::array();
  for (const ToolReach& r : reach) {
    std::size_t o = 0;
    while (scene.obstacles[o].name != r.tool) ++o;
    nlohmann::json t = {{"tool", r.tool},
                        {"touches", r.touches()},
                        {"clearance_m", r.clearance_m},
                        {r.by_time ? "at_time_s" : "at_load_factor", r.at}};
    if (!r.touches()) t["warning"] = tool_reach_warning(r, scene.obstacles[o], o);
    tools.push_back(t);
  }
  return tools;
}

nlohmann::json check_report(const Scene& scene, Built& b, double setup_s) {
  Simulation& sim = *b.sim;
  nlohmann::json report = describe_run(scene, sim);
  report["setup_s"] = setup_s;
  report["model_steps"] = b.steps;
  const CostCalibration* calibration = bundled_cost_calibration();
  const std::optional<CostEstimate> cost =
      calibration ? estimate_run_cost(*calibration, scene, sim, b.steps) : std::nullopt;
  if (cost)
    report["expected_time"] = {{"step", cost->step},
                               {"steps", cost->steps},
                               {"seconds_per_step", cost->seconds_per_step},
                               {"total_s", cost->total_s},
                               {"factor", cost->factor},
                               {"calibration_runs", cost->runs},
                               {"extrapolated", cost->extrapolated},
                               {"text", describe_cost(*cost)}};
  else
    report["expected_time"] = {{"text", calibration ? fmt::format("no calibration for model '{}' in {}",
                                                                  scene.model, calibration->file.string())
                                                    : std::string("no cost calibration found")}};
  if (b.session && b.session->inputs().mode == "realtime")
    report["expected_time"]["text"] =
        report["expected_time"]["text"].get<std::string>() +
        fmt::format(
            "; a realtime session lasts its {:.3g} s whatever its frames cost (a slower frame falls behind "
            "the hand)",
            b.session->inputs().duration_s);
  report["memory"] = memory_report(sim, cost);
  if (const ForceAccuracyTable* table = bundled_force_accuracy()) {
    const AccuracyEstimate a = estimate_accuracy(*table, scene, sim.discretization().num_nodes());
    report["expected_force_error"] = {{"text", describe_accuracy(*table, a)}};
    if (a.match)
      report["expected_force_error"].update({{"error", a.error}, {"case", a.match->name}});
    else
      report["expected_force_error"]["estimate_with"] = fmt::format("vascsim converge {}", scene.file);
    report["warnings"] = model_accuracy_warnings(*table, scene, sim);
  }
  nlohmann::json regions = nlohmann::json::array();
  for (const Region& r : sim.problem().regions())
    regions.push_back({{"name", r.name}, {"bc", bc_name(r.bc)}, {"nodes", r.nodes.size()}});
  report["regions"] = regions;
  report["tools"] = tools_report(scene, b.reach);
  if (scene.output.surface && sim.body().surface) report["surface_map"] = surface_map_info(sim);
  return report;
}

void print_report(const Scene& scene, const nlohmann::json& r, std::ostream& out) {
  const int threads = r["threads"].get<int>();
  out << fmt::format("{} ({}): model {}, {} thread{}; built in {:.2f} s, nothing solved\n", scene.name,
                     scene.file, scene.model, threads, threads == 1 ? "" : "s", r["setup_s"].get<double>());
  out << fmt::format(
      "  body      {} nodes, {} neighbour pairs ({:.1f} per node), mean spacing {:.4g} m, {} nodes "
      "with grown support\n",
      r["nodes"].get<long long>(), r["neighbour_pairs"].get<long long>(), r["mean_neighbours"].get<double>(),
      r["mean_spacing_m"].get<double>(), r["nodes_with_grown_support"].get<long long>());
  const auto& m = r["memory"];
  std::string memory = fmt::format("resident {} after building (the model's set-up included)",
                                   mib(m["resident_after_build_bytes"].get<double>()));
  if (m.contains("factor_bytes"))
    memory += fmt::format(", of it the preconditioner's factor {}", mib(m["factor_bytes"].get<double>()));
  if (m.contains("expected_run_peak"))
    memory += fmt::format("; the run's peak about {} (within a factor {:.2g} either way)",
                          mib(m["expected_run_peak"]["bytes"].get<double>()),
                          m["expected_run_peak"]["factor"].get<double>());
  out << "  memory    " << memory << "\n";
  out << "  time      " << r["expected_time"]["text"].get<std::string>() << "\n";
  if (r.contains("expected_force_error")) {
    out << "  accuracy  expected force error " << r["expected_force_error"]["text"].get<std::string>()
        << "\n";
    if (r["expected_force_error"].contains("estimate_with"))
      out << "  accuracy  this scene's own discretisation error, with its bound: "
          << r["expected_force_error"]["estimate_with"].get<std::string>() << " (docs/convergence.md)\n";
  }
  if (r.contains("surface_map")) {
    const auto& s = r["surface_map"];
    out << fmt::format(
        "  surface   {} vertices mapped from {:.1f} nodes each (min {}, max {}), max cond {:.3g}, {} "
        "vertices grown\n",
        s["vertices"].get<long long>(), s["mean_support"].get<double>(), s["min_support"].get<long long>(),
        s["max_support"].get<long long>(), s["max_cond"].get<double>(), s["grown_vertices"].get<long long>());
  }
  for (const auto& g : r["regions"])
    out << fmt::format("  region    {}: {}, {} nodes\n", g["name"].get<std::string>(),
                       g["bc"].get<std::string>(), g["nodes"].get<long long>());
  for (const auto& t : r["tools"]) {
    const bool by_time = t.contains("at_time_s");
    const double at = by_time ? t["at_time_s"].get<double>() : t["at_load_factor"].get<double>();
    const std::string where =
        by_time ? fmt::format("t = {:.3g} s", at) : fmt::format("load factor {:.3g}", at);
    out << fmt::format(
        "  tool      {}: {}\n", t["tool"].get<std::string>(),
        t["touches"].get<bool>()
            ? fmt::format("reaches the tissue (its contact surface passes {:.3g} m into the nodes at {})",
                          -t["clearance_m"].get<double>(), where)
            : t["warning"].get<std::string>());
  }
  if (scene.instrument) {
    const rod::InstrumentSpec& i = *scene.instrument;
    const rod::RodStiffness k = rod::rod_stiffness(i.section);
    out << fmt::format(
        "  instrument {}: {:.3g} mm across{}, EI {:.3g} N m^2, GJ {:.3g} N m^2, {:.0f} mm in edges of {:.3g} "
        "mm, "
        "friction {:.3g}; driven {:.1f} to {:.1f} mm over {:.3g} s: `vascsim navigate` runs it in the rigid "
        "lumen (`run` simulates the wall alone)\n",
        i.name, i.section.outer_diameter_m * 1e3,
        i.section.inner_diameter_m > 0.0 ? fmt::format(" (lumen {:.3g} mm)", i.section.inner_diameter_m * 1e3)
                                         : std::string(),
        k.bend_twist_n_m2[0], k.bend_twist_n_m2[2], i.length_m * 1e3, i.edge_length_m * 1e3, i.friction,
        i.drive.front().inserted_m * 1e3, i.drive.back().inserted_m * 1e3, i.drive.back().time_s);
  }
  if (r.contains("warnings"))
    for (const auto& w : r["warnings"]) out << "  warning   " << w.get<std::string>() << "\n";
}

int check(const CheckFlags& flags, CliContext& ctx) {
  const Scene scene = load_scene(flags.scene, flags.sets);
  const Stopwatch setup;
  Built built = build(scene, flags.yes);
  const nlohmann::json report = check_report(scene, built, setup.seconds());
  print_report(scene, report, ctx.out);
  if (!flags.json.empty()) {
    write_file_atomically(flags.json, report.dump(2) + "\n");  // whole or not at all, errors named
  }
  return 0;
}

}  // namespace

void add_check_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto flags = std::make_shared<CheckFlags>();
  CLI::App* check_app = app.add_subcommand(
      "check",
      "Build a scene as `run` would, solve nothing, and report its size, memory, expected time and force "
      "accuracy, regions and tools (exit code 2 where `run` would fail on input)");
  check_app->add_option("scene", flags->scene, "Scene JSON file (docs/scene-format.md)")->required();
  check_app->add_option("--set", flags->sets, "Override a scene key: path.to.key=value (repeatable)");
  check_app->add_flag(
      "--yes", flags->yes,
      fmt::format("Build a body of more than {} nodes (otherwise refused as by run)", kMaxNodesUnasked));
  check_app->add_option("--json", flags->json, "Also write the report to this JSON file");
  commands.push_back({check_app, [flags, &ctx] { return check(*flags, ctx); }});
}

}  // namespace vascsim
