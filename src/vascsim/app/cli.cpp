#include "vascsim/app/cli.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <omp.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "vascsim/app/progress.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/ahp_evaluation.hpp"
#include "vascsim/experiments/ahp_report.hpp"
#include "vascsim/experiments/cantilever.hpp"
#include "vascsim/experiments/force_displacement.hpp"
#include "vascsim/experiments/mls_validation.hpp"
#include "vascsim/experiments/realtime_bench.hpp"
#include "vascsim/scene/haptic_session.hpp"
#include "vascsim/scene/runner.hpp"

namespace vascsim {

namespace {

bool is_terminal(const std::ostream& s) { return &s == &std::cerr && isatty(STDERR_FILENO); }

void setup_logging(std::ostream& err, bool quiet, bool verbose) {
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(err);
  auto logger = std::make_shared<spdlog::logger>("vascsim", sink);
  logger->set_pattern("[%l] %v");
  logger->set_level(quiet ? spdlog::level::warn : verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_default_logger(logger);
}

std::string step_status(const std::string& model, const StepRecord& r) {
  if (r.step == 0) return "rest state";
  if (model == "quasi_static")
    return fmt::format("load {:.3f}: {} Newton / {} CG it., residual {:.1e}{}", r.report.load_factor,
                       r.report.iterations, r.report.inner_iterations, r.report.residual,
                       r.report.converged ? "" : " NOT CONVERGED");
  return fmt::format("t = {:.4g} s, {} substeps", r.report.time_s, r.report.iterations);
}

struct SessionFlags {
  std::string mode, record, replay;
};

int command_haptic_session(const Scene& scene, const std::filesystem::path& out_dir, const SessionFlags& flags,
                           std::ostream& out, std::ostream& err) {
  spdlog::info("scene '{}' ({}): haptic session, output {}", scene.name, scene.file, out_dir.string());
  Progress progress(err, is_terminal(err), scene.name);
  HapticRunOptions opt;
  opt.out_dir = out_dir;
  opt.mode = flags.mode;
  opt.record = flags.record;
  opt.replay = flags.replay;
  opt.on_progress = [&](double done, double total) {
    progress.update(static_cast<int>(std::lround(1000.0 * done / total)), 1000,
                    fmt::format("session t = {:.3f} of {:.3f} s", done, total));
  };
  const nlohmann::json summary = run_haptic_session(scene, opt);
  progress.finish();
  const auto& h = summary["haptics"];
  const auto& loop = h["loop"];
  out << fmt::format("{}: {} nodes, {:.3g} s session ({}), {} ticks at {:.1f} Hz (jitter p50/p99/max {:.3f}/{:.3f}/{:.3f} "
                     "ms), {} simulation steps at {:.1f} Hz, max force on the tool {:.4g} N; wrote {}\n",
                     scene.name, summary["nodes"].get<int>(), h["duration_s"].get<double>(), h["mode"].get<std::string>(),
                     h["ticks"].get<std::size_t>(), loop["achieved_rate_hz"].get<double>(),
                     loop["jitter_p50_ms"].get<double>(), loop["jitter_p99_ms"].get<double>(),
                     loop["jitter_max_ms"].get<double>(), h["simulation_steps"].get<std::size_t>(),
                     h["deformation_rate_hz"].get<double>(), h["max_force_on_tool_n"].get<double>(),
                     (out_dir / "force_history.csv").string());
  if (h.contains("replay"))
    out << fmt::format("replay of {}: {} ticks compared, max force difference {:.3g} N, bit-identical: {}\n",
                       h["replay"]["file"].get<std::string>(), h["replay"]["ticks_compared"].get<std::size_t>(),
                       h["replay"]["max_force_difference_n"].get<double>(),
                       h["replay"]["bit_identical"].get<bool>() ? "yes" : "no");
  return 0;
}

int command_run(const std::string& scene_path, const std::vector<std::string>& sets, const std::string& out_opt,
                const SessionFlags& flags, std::ostream& out, std::ostream& err) {
  const Scene scene = load_scene(scene_path, sets);
  const std::filesystem::path out_dir = out_opt.empty() ? std::filesystem::path("out") / scene.name : std::filesystem::path(out_opt);
  if (scene.haptics.enabled) return command_haptic_session(scene, out_dir, flags, out, err);
  if (!flags.mode.empty() || !flags.record.empty() || !flags.replay.empty())
    throw InputError(fmt::format("{}: --mode, --record and --replay need a scene with a 'haptics' block", scene.file));
  spdlog::info("scene '{}' ({}), model {}, output {}", scene.name, scene.file, scene.model, out_dir.string());
  Progress progress(err, is_terminal(err), scene.name);
  RunOptions opt;
  opt.out_dir = out_dir;
  opt.on_step = [&](const StepRecord& r, int total) { progress.update(r.step, total, step_status(scene.model, r)); };
  const nlohmann::json summary = run_scene(scene, opt);
  progress.finish();
  out << fmt::format("{}: {} nodes, {} steps in {:.2f} s (setup {:.2f} s); wrote {}\n", scene.name,
                     summary["nodes"].get<int>(), summary["steps"].size() - 1,
                     summary["timings_s"]["total"].get<double>(), summary["timings_s"]["setup"].get<double>(),
                     (out_dir / "summary.json").string());
  if (summary.contains("reference")) {
    const auto& ref = summary["reference"];
    out << fmt::format("tip deflection {:.6g} m, Timoshenko reference {:.6g} m, ratio {:.4f}\n",
                       ref["tip_deflection_m"].get<double>(), ref["reference_deflection_m"].get<double>(),
                       ref["ratio"].get<double>());
  }
  if (summary["unconverged_steps"].get<int>() > 0)
    out << fmt::format("warning: {} load steps did not converge (see summary.json)\n",
                       summary["unconverged_steps"].get<int>());
  return 0;
}

int command_force_displacement(const std::string& scene_path, const std::vector<std::string>& sets,
                               const std::string& out_opt, const std::string& tool, bool plot, std::ostream& out,
                               std::ostream& err) {
  const Scene scene = load_scene(scene_path, sets);
  ForceDisplacementOptions opt;
  opt.out_dir = out_opt.empty() ? std::filesystem::path("out") / (scene.name + "-force-displacement")
                                : std::filesystem::path(out_opt);
  opt.tool = tool;
  opt.plot = plot;
  spdlog::info("force-displacement: scene '{}' ({}), model {}, output {}", scene.name, scene.file, scene.model,
               opt.out_dir.string());
  Progress progress(err, is_terminal(err), scene.name);
  opt.on_step = [&](const StepRecord& r, int total) { progress.update(r.step, total, step_status(scene.model, r)); };
  const ForceDisplacementResult res = run_force_displacement(scene, opt);
  progress.finish();
  const auto& rows = res.summary["force_displacement"]["rows"];
  const auto& last = rows.back();
  out << fmt::format("{}: tool '{}' at {:.4g} mm: {:.4g} mN ({} steps, model {}); wrote {}\n", scene.name,
                     res.summary["force_displacement"]["tool"].get<std::string>(),
                     last["displacement_m"].get<double>() * 1e3, last["force_n"].get<double>() * 1e3,
                     rows.size() - 1, scene.model, res.csv.string());
  if (!res.png.empty()) out << "wrote " << res.png.string() << "\n";
  if (!res.plot_problem.empty()) out << "warning: no plot: " << res.plot_problem << "\n";
  if (res.summary["unconverged_steps"].get<int>() > 0)
    out << fmt::format("warning: {} load steps did not converge (see summary.json)\n",
                       res.summary["unconverged_steps"].get<int>());
  return 0;
}

int command_validate_mls(const std::vector<std::string>& scenes, const std::vector<std::string>& sets,
                         double tight_factor, const std::string& out_opt, std::ostream& out) {
  const nlohmann::json rows = validate_mls(scenes, sets, tight_factor);
  const std::filesystem::path dir = out_opt.empty() ? std::filesystem::path("out/mls-validation") : std::filesystem::path(out_opt);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the output folder: {}", dir.string(), ec.message()));
  const std::string table = mls_validation_table(rows);
  std::ofstream(dir / "mls-validation.json") << rows.dump(2) << "\n";
  std::ofstream(dir / "mls-validation.md") << table;
  out << table << "wrote " << (dir / "mls-validation.json").string() << " and mls-validation.md\n";
  bool all = true;
  for (const auto& r : rows) all = all && r["t11_pass"].get<bool>();
  return all ? 0 : 1;
}

int command_validate_cantilever(const std::string& out_opt, const std::vector<int>& sizes, std::ostream& out,
                                std::ostream& err) {
  struct Row {
    std::string label;
    CantileverCase base;
  };
  CantileverCase sound;
  auto with = [&](auto change) {
    CantileverCase c = sound;
    change(c);
    return c;
  };
  const std::vector<Row> rows = {
      {"sound, nu = 0.3", with([](auto& c) { c.poisson_ratio = 0.3; })},
      {"sound, nu = 0.45", sound},
      {"sound, K_min = 4 (no support growth at edges), nu = 0.3",
       with([](auto& c) { c.poisson_ratio = 0.3; c.min_neighbours = 4; })},
      {"sound, K_min = 4 (no support growth at edges), nu = 0.45", with([](auto& c) { c.min_neighbours = 4; })},
      {"sound without stabiliser (alpha_hg = 0), nu = 0.45", with([](auto& c) { c.stabilizer_alpha = 0.0; })},
      {"h = 1.5 Delta, nu = 0.45", with([](auto& c) { c.support_radius_factor = 1.5; })},
      {"alpha_hg = 0.5, nu = 0.45", with([](auto& c) { c.stabilizer_alpha = 0.5; })},
      {"Mueller-kernel volumes, nu = 0.45", with([](auto& c) { c.volume = "mueller_kernel"; })},
      {"literal strain (no 1/2), alpha_hg = 0, nu = 0.45",
       with([](auto& c) { c.strain = "mueller_no_half"; c.stabilizer_alpha = 0.0; })}};
  const std::filesystem::path dir = out_opt.empty() ? std::filesystem::path("out/cantilever-table") : std::filesystem::path(out_opt);
  std::filesystem::create_directories(dir);
  std::ofstream csv(dir / "cantilever-table.csv");
  csv << "configuration,n,nodes,tip_deflection_m,reference_m,ratio,newton_iterations,residual,seconds\n";
  std::string md = "| configuration |";
  for (int n : sizes) md += fmt::format(" n = {} |", n);
  md += "\n|---|";
  for (std::size_t i = 0; i < sizes.size(); ++i) md += "---|";
  md += "\n";
  Progress progress(err, is_terminal(err), "cantilever");
  const int total = static_cast<int>(rows.size() * sizes.size());
  int done = 0;
  for (const Row& row : rows) {
    md += "| " + row.label + " |";
    for (int n : sizes) {
      CantileverCase c = row.base;
      c.cells_across = n;
      const CantileverResult r = run_cantilever(c);
      csv << fmt::format("\"{}\",{},{},{:.9g},{:.9g},{:.6f},{},{:.3g},{:.3f}\n", row.label, n, r.nodes,
                         r.tip_deflection_m, r.reference_m, r.ratio, r.newton_iterations, r.residual, r.seconds);
      csv.flush();
      md += fmt::format(" {:.3f} |", r.ratio);
      progress.update(++done, total, fmt::format("{} n={}: ratio {:.4f}", row.label, n, r.ratio));
    }
    md += "\n";
  }
  progress.finish();
  std::ofstream(dir / "cantilever-table.md") << md;
  out << "delta / delta_Timoshenko (tip load, L/b = 10, clamp = 3 node layers, quasi-static):\n\n" << md;
  out << fmt::format("\nwrote {} and {}\n", (dir / "cantilever-table.csv").string(), (dir / "cantilever-table.md").string());
  return 0;
}

int command_bench(RealtimeBenchOptions opt, const std::vector<std::string>& outs, bool quiet, bool verbose,
                  std::ostream& out, std::ostream& err) {
  // Check the output names before minutes of timing.
  for (const auto& f : outs) {
    const auto ext = std::filesystem::path(f).extension();
    if (ext != ".csv" && ext != ".json")
      throw InputError(fmt::format("bench: --out '{}' must end in .csv or .json (give --out twice for both)", f));
  }
  // Every configuration builds a Simulation, whose set-up log lines would bury the results.
  if (!verbose) spdlog::default_logger()->set_level(spdlog::level::warn);
  if (!quiet) opt.progress = [&err](const std::string& line) { err << line << std::endl; };
  const RealtimeBenchReport report = run_realtime_bench(opt);
  out << realtime_bench_table(report);
  for (const auto& f : outs) {
    const std::filesystem::path path(f);
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream file(path);
    if (path.extension() == ".csv")
      file << realtime_bench_csv(report);
    else
      file << realtime_bench_json(report).dump(2) << "\n";
    if (!file) throw InputError(fmt::format("bench: cannot write {}", f));
    out << "wrote " << f << "\n";
  }
  return 0;
}

struct AhpFlags {
  std::string hierarchy, bands, ratings, measurements, out = "out/ahp";
  bool no_plot = false, paper_weights = false;
};

int command_ahp(const AhpFlags& f, std::ostream& out) {
  const std::filesystem::path data = ahp::default_data_dir();
  ahp::AhpInputs in;
  in.hierarchy = f.hierarchy.empty() ? data / "paper-hierarchy.json" : std::filesystem::path(f.hierarchy);
  in.bands = f.bands.empty() ? data / "paper-bands.json" : std::filesystem::path(f.bands);
  in.ratings = f.ratings.empty() ? data / "paper-ratings.json" : std::filesystem::path(f.ratings);
  if (!f.measurements.empty()) in.measurements = f.measurements;
  in.paper_weights = f.paper_weights;
  const ahp::AhpReport report = ahp::run_ahp(in);
  ahp::OutputOptions opt;
  opt.out_dir = f.out;
  opt.plot = !f.no_plot;
  const ahp::Outputs written = ahp::write_outputs(report, opt);
  out << ahp::markdown(report) << "\n";
  for (const auto& p : written.files) out << "wrote " << p.string() << "\n";
  if (!written.png.empty()) out << "wrote " << written.png.string() << "\n";
  if (!written.plot_problem.empty()) out << "warning: no plot: " << written.plot_problem << "\n";
  return 0;
}

}  // namespace

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"vascsim: point-primitive vascular tissue simulation (Zhang et al. 2021, with the fixes of MODEL.md)"};
  app.require_subcommand(1);
  bool quiet = false, verbose = false;
  int threads = 0;
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors on stderr");
  app.add_flag("-v,--verbose", verbose, "Debug logging");
  app.add_option("-j,--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));

  auto* run = app.add_subcommand("run", "Run a scene headless and write summary.json, probes.csv (and VTK)");
  std::string scene_path, out_dir;
  std::vector<std::string> sets;
  run->add_option("scene", scene_path, "Scene JSON file (docs/scene-format.md)")->required();
  run->add_option("--set", sets, "Override a scene key: path.to.key=value (repeatable)");
  run->add_option("--out", out_dir, "Output folder (default: out/<scene name>)");
  SessionFlags session;
  run->add_option("--mode", session.mode, "Haptic scenes: lockstep (deterministic) or realtime (haptic thread)")
      ->check(CLI::IsMember({"lockstep", "realtime"}));
  run->add_option("--record", session.record, "Haptic scenes: also write the session recording to FILE");
  run->add_option("--replay", session.replay, "Haptic scenes: play a session recording instead of the trajectory");

  auto* validate = app.add_subcommand("validate", "Validation studies against analytic references");
  validate->require_subcommand(1);
  auto* cant = validate->add_subcommand("cantilever", "MODEL.md T9: cantilever convergence table");
  std::vector<int> sizes = {2, 3, 4, 6};
  cant->add_option("--out", out_dir, "Output folder (default: out/cantilever-table)");
  cant->add_option("--sizes", sizes, "Cells across the beam, n = b / Delta")->delimiter(',')->check(CLI::Range(1, 16));

  auto* mls = validate->add_subcommand("mls", "MODEL.md T11/T15: the MLS surface map of each scene's body");
  std::vector<std::string> mls_scenes;
  double mls_tight = 1.0;
  mls->add_option("scenes", mls_scenes, "Scene JSON files")->required();
  mls->add_option("--set", sets, "Override a key in every scene: path.to.key=value (repeatable)");
  mls->add_option("--tight-factor", mls_tight, "Support radius factor for the T15 guard check")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 5.0));
  mls->add_option("--out", out_dir, "Output folder (default: out/mls-validation)");

  auto* bench = app.add_subcommand("bench", "Real-time benchmark: wall time per 1 ms step at several resolutions "
                                            "(docs/performance.md section 9)");
  RealtimeBenchOptions bench_opt;
  bench_opt.scene_path = "scenes/vein-indent.json";
  std::vector<std::string> bench_out;
  bench->add_option("scene", bench_opt.scene_path, "Scene JSON file with a tube geometry")->capture_default_str();
  bench->add_option("--model", bench_opt.model, "Model to time (xpbd or explicit)")->capture_default_str();
  bench->add_option("--nodes", bench_opt.target_nodes, "Target node counts (the nearest tube resolution is used)")
      ->delimiter(',')
      ->capture_default_str();
  auto* bench_threads =
      bench->add_option("--threads", bench_opt.threads, "OpenMP thread counts (default 1,2; or -j N)")->delimiter(',');
  bench->add_option("--steps", bench_opt.steps, "Timed 1 ms steps per configuration")->capture_default_str();
  bench->add_option("--warmup", bench_opt.warmup_steps, "Untimed steps before them")->capture_default_str();
  bench->add_option("--set", bench_opt.overrides, "Override a scene key: path.to.key=value (repeatable)");
  bench->add_option("--out", bench_out, "Write FILE.csv or FILE.json (repeatable: --out a.csv --out a.json)");

  auto* experiment = app.add_subcommand("experiment", "The paper's experiments, one command each");
  experiment->require_subcommand(1);
  auto* fd = experiment->add_subcommand(
      "force-displacement", "A tool (catheter) presses the vessel in displacement steps: force_displacement.csv "
                            "and .png (the paper's Fig. 10: scenes/hand-dorsal-vein-catheter.json)");
  std::string fd_tool;
  bool fd_no_plot = false;
  fd->add_option("scene", scene_path, "Scene JSON file with a moving tool in 'obstacles'")->required();
  fd->add_option("--set", sets, "Override a scene key: path.to.key=value (repeatable), e.g. model=xpbd");
  fd->add_option("--out", out_dir, "Output folder (default: out/<scene name>-force-displacement)");
  fd->add_option("--tool", fd_tool, "The obstacle that presses (default: the scene's only obstacle)");
  fd->add_flag("--no-plot", fd_no_plot, "Write the CSV only (no matplotlib call)");

  auto* ahp_cmd = app.add_subcommand(
      "ahp", "The paper's AHP evaluation (Tables 1-3, Eq. 40): weights and consistency of the pairwise matrices, the "
             "score table of all models and a figure (docs/ahp.md); default inputs: the bundled data/ahp files");
  AhpFlags ahp_flags;
  ahp_cmd->add_option("--hierarchy", ahp_flags.hierarchy, "Hierarchy with pairwise matrices (default: paper-hierarchy.json)");
  ahp_cmd->add_option("--bands", ahp_flags.bands, "Evaluation standard, Table 2 (default: paper-bands.json)");
  ahp_cmd->add_option("--ratings", ahp_flags.ratings, "Indicator ratings per model (default: paper-ratings.json)");
  ahp_cmd->add_option("--measurements", ahp_flags.measurements,
                      "Measured figures per model (data/ahp/measurements.schema.json; default: none)");
  ahp_cmd->add_option("--out", ahp_flags.out, "Output folder")->capture_default_str();
  ahp_cmd->add_flag("--no-plot", ahp_flags.no_plot, "Write the tables only (no matplotlib call)");
  ahp_cmd->add_flag("--paper-weights", ahp_flags.paper_weights,
                    "Use Table 1's printed W_i in Eq. 40 instead of the weights computed from the matrices");

  // Global options (-q, -v, -j) are accepted after the subcommand too.
  for (auto* sub : {run, validate, cant, mls, bench, experiment, fd, ahp_cmd}) sub->fallthrough();
  std::vector<std::string> rev(args.rbegin(), args.rend());
  try {
    app.parse(rev);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    out << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::ParseError& e) {
    err << "vascsim: " << e.what() << " (see vascsim --help)\n";
    return 2;
  }
  // The logger writes to `err`, which may not outlive this call: restore the previous one on return.
  struct RestoreLogger {
    std::shared_ptr<spdlog::logger> previous = spdlog::default_logger();
    ~RestoreLogger() { spdlog::set_default_logger(previous); }
  } restore_logger;
  setup_logging(err, quiet, verbose);
  if (threads > 0) omp_set_num_threads(threads);
  try {
    if (run->parsed()) return command_run(scene_path, sets, out_dir, session, out, err);
    if (cant->parsed()) return command_validate_cantilever(out_dir, sizes, out, err);
    if (fd->parsed()) return command_force_displacement(scene_path, sets, out_dir, fd_tool, !fd_no_plot, out, err);
    if (mls->parsed()) return command_validate_mls(mls_scenes, sets, mls_tight, out_dir, out);
    if (ahp_cmd->parsed()) return command_ahp(ahp_flags, out);
    if (bench->parsed()) {
      if (bench_threads->count() == 0 && threads > 0) bench_opt.threads = {threads};
      return command_bench(bench_opt, bench_out, quiet, verbose, out, err);
    }
  } catch (const InputError& e) {
    err << "vascsim: error: " << e.what() << "\n";
    return 2;
  } catch (const NumericalError& e) {
    err << "vascsim: numerical error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    err << "vascsim: internal error (please report): " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace vascsim
