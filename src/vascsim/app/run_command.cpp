// `vascsim run SCENE.json`: a headless run of a scene (load steps or output times), or a haptic session when
// the scene has a `haptics` block.

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <filesystem>

#include "vascsim/app/command.hpp"
#include "vascsim/app/progress.hpp"
#include "vascsim/app/run_limits.hpp"
#include "vascsim/app/step_status.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/run_assessment.hpp"
#include "vascsim/run/haptic_session.hpp"
#include "vascsim/run/runner.hpp"

namespace vascsim {

namespace {

struct RunFlags {
  std::string scene, out;
  std::vector<std::string> sets;
  std::string mode, record, replay;  // haptic sessions
  bool yes = false;                  // start a large run without asking (run_limits.hpp)
};

// The warnings of summary.json again at the end, where they are seen.
void print_warnings(const nlohmann::json& summary, CliContext& ctx) {
  if (!summary.contains("warnings")) return;
  for (const auto& w : summary["warnings"]) ctx.out << "warning: " << w.get<std::string>() << "\n";
}

int run_session(const Scene& scene, const std::filesystem::path& out_dir, const RunFlags& flags,
                CliContext& ctx) {
  spdlog::info("scene '{}' ({}): haptic session, model {}, output {}", scene.name, scene.file, scene.model,
               out_dir.string());
  Progress progress(ctx.err, ctx.err_is_terminal(), scene.name, ctx.quiet);
  HapticRunOptions opt;
  opt.out_dir = out_dir;
  opt.mode = flags.mode;
  opt.record = flags.record;
  opt.replay = flags.replay;
  opt.on_progress = [&](double done, double total) {
    progress.update(static_cast<int>(std::lround(1000.0 * done / total)), 1000,
                    fmt::format("session t = {:.3f} of {:.3f} s", done, total));
  };
  opt.checks = node_limit(scene, flags.yes);
  opt.after_setup = [&](Simulation& sim, double frames) {
    const std::string mode = flags.mode.empty() ? scene.haptics.mode : flags.mode;
    announce_run(scene, sim, frames, flags.yes, mode == "realtime");
  };
  const nlohmann::json summary = run_haptic_session(scene, opt);
  progress.finish();
  const auto& h = summary["haptics"];
  const auto& loop = h["loop"];
  ctx.out << fmt::format(
      "{}: {} nodes, {:.3g} s session ({}), {} ticks at {:.1f} Hz (jitter p50/p99/max {:.3f}/{:.3f}/{:.3f} "
      "ms), {} "
      "simulation steps at {:.1f} Hz, max force on the tool {:.4g} N; wrote {}\n",
      scene.name, summary["nodes"].get<int>(), h["duration_s"].get<double>(), h["mode"].get<std::string>(),
      h["ticks"].get<std::size_t>(), loop["achieved_rate_hz"].get<double>(),
      loop["jitter_p50_ms"].get<double>(), loop["jitter_p99_ms"].get<double>(),
      loop["jitter_max_ms"].get<double>(), h["simulation_steps"].get<std::size_t>(),
      h["deformation_rate_hz"].get<double>(), h["max_force_on_tool_n"].get<double>(),
      (out_dir / "force_history.csv").string());
  if (h["mode"].get<std::string>() == "realtime") {
    // What the hand got, beside the model: in realtime the frames come at their own pace and the loop extends
    // the last one's force to the hand's pose, so the model's force and the hand's differ under motion.
    ctx.out << fmt::format(
        "the hand: the force it felt came from frames {:.0f} ms old on average ({:.0f} ms at most) at {:.1f} "
        "frames/s; "
        "the model's tool stayed at most {:.3g} mm behind the device; force sent to the hand at most {:.4g} "
        "N, the "
        "model's frames at most {:.4g} N (between frames the loop extends the last frame's force with its "
        "stiffness "
        "to the hand's pose; docs/haptics.md)\n",
        loop["force_latency_mean_ms"].get<double>(), loop["force_latency_max_ms"].get<double>(),
        h["deformation_rate_hz"].get<double>(), 1e3 * h["max_tool_lag_m"].get<double>(),
        loop["max_force_sent_n"].get<double>(), h["max_force_on_tool_n"].get<double>());
  }
  if (summary["interrupted"].get<bool>())
    ctx.out << "interrupted: summary.json, force_history.csv, session.csv and haptic_ticks.csv hold the "
               "ticks done\n";
  if (h.contains("replay"))
    ctx.out << fmt::format(
        "replay of {}: {} ticks compared, max force difference {:.3g} N, bit-identical: {}\n",
        h["replay"]["file"].get<std::string>(), h["replay"]["ticks_compared"].get<std::size_t>(),
        h["replay"]["max_force_difference_n"].get<double>(),
        h["replay"]["bit_identical"].get<bool>() ? "yes" : "no");
  print_warnings(summary, ctx);
  const auto unconverged = summary["unconverged_frames"].get<long long>();
  if (unconverged == 0) return 0;
  // Realtime frames stop at their time budget or iteration limit by design (the next frame goes on from
  // there); a lockstep frame takes the time it needs.
  if (h["mode"].get<std::string>() == "realtime") {
    ctx.out << fmt::format(
        "note: {} of {} frames ended before converging (a realtime frame stops at its time budget or "
        "iteration limit; the next frame goes on from there)\n",
        unconverged, h["simulation_steps"].get<std::size_t>());
    return 0;
  }
  ctx.out << fmt::format(
      "NOT CONVERGED: {} of {} frames did not reach the tolerance; the forces of those frames are "
      "not equilibria (force_history.csv, column converged)\n",
      unconverged, h["simulation_steps"].get<std::size_t>());
  return kExitUnconverged;
}

int run_headless(const Scene& scene, const std::filesystem::path& out_dir, const RunFlags& flags,
                 CliContext& ctx) {
  spdlog::info("scene '{}' ({}), model {}, output {}", scene.name, scene.file, scene.model, out_dir.string());
  if (scene.instrument)
    spdlog::info(
        "the scene's instrument '{}' is not part of this run (the wall alone): `vascsim navigate {}` runs it "
        "in the vessel's lumen",
        scene.instrument->name, scene.file);
  Progress progress(ctx.err, ctx.err_is_terminal(), scene.name, ctx.quiet);
  RunOptions opt;
  opt.out_dir = out_dir;
  opt.checks = node_limit(scene, flags.yes);
  opt.after_setup = [&](Simulation& sim) {
    const CostCalibration* calibration = bundled_cost_calibration();
    const ModelCost* cost = calibration ? calibration->find(scene.model) : nullptr;
    announce_run(scene, sim, headless_model_steps(scene, sim, cost), flags.yes);
  };
  opt.on_step = [&](const StepRecord& r, int total) {
    progress.update(r.step, total, step_status(scene.model, r));
  };
  const nlohmann::json summary = run_scene(scene, opt);
  progress.finish();
  ctx.out << fmt::format("{}: {} nodes, {} steps in {:.2f} s (setup {:.2f} s); wrote {}\n", scene.name,
                         summary["nodes"].get<int>(), summary["steps"].size() - 1,
                         summary["timings_s"]["total"].get<double>(),
                         summary["timings_s"]["setup"].get<double>(), (out_dir / "summary.json").string());
  if (summary.contains("reference")) {
    const auto& ref = summary["reference"];
    ctx.out << fmt::format("tip deflection {:.6g} m, Timoshenko reference {:.6g} m, ratio {:.4f}\n",
                           ref["tip_deflection_m"].get<double>(), ref["reference_deflection_m"].get<double>(),
                           ref["ratio"].get<double>());
  }
  if (summary["interrupted"].get<bool>())
    ctx.out << fmt::format(
        "interrupted after step {} of {}: summary.json, probes.csv and the VTK series hold the "
        "steps done\n",
        summary["steps"].size() - 1, summary["planned_steps"].get<int>());
  print_warnings(summary, ctx);
  const int unconverged = summary["unconverged_steps"].get<int>();
  if (unconverged == 0) return 0;
  ctx.out << fmt::format(
      "NOT CONVERGED: {} of {} steps did not reach the tolerance; their forces and displacements "
      "are not equilibria (summary.json, steps[].converged)\n",
      unconverged, summary["steps"].size() - 1);
  return kExitUnconverged;
}

int run(const RunFlags& flags, CliContext& ctx) {
  const Scene scene = load_scene(flags.scene, flags.sets);
  const std::filesystem::path out_dir =
      flags.out.empty() ? std::filesystem::path("out") / scene.name : std::filesystem::path(flags.out);
  if (scene.haptics.enabled) return run_session(scene, out_dir, flags, ctx);
  if (!flags.mode.empty() || !flags.record.empty() || !flags.replay.empty())
    throw InputError(
        fmt::format("{}: --mode, --record and --replay need a scene with a 'haptics' block", scene.file));
  return run_headless(scene, out_dir, flags, ctx);
}

}  // namespace

void add_run_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto flags = std::make_shared<RunFlags>();
  CLI::App* run_app =
      app.add_subcommand("run", "Run a scene headless and write summary.json, probes.csv (and VTK)");
  run_app->add_option("scene", flags->scene, "Scene JSON file (docs/scene-format.md)")->required();
  run_app->add_option("--set", flags->sets, "Override a scene key: path.to.key=value (repeatable)");
  run_app->add_option("--out", flags->out, "Output folder (default: out/<scene name>)");
  run_app
      ->add_option("--mode", flags->mode,
                   "Haptic scenes: lockstep (deterministic) or realtime (haptic thread)")
      ->check(CLI::IsMember({"lockstep", "realtime"}));
  run_app->add_option("--record", flags->record, "Haptic scenes: also write the session recording to FILE");
  run_app->add_option("--replay", flags->replay,
                      "Haptic scenes: play a session recording instead of the trajectory");
  run_app->add_flag(
      "--yes", flags->yes,
      fmt::format("Start a run of more than {} nodes or expected to take more than {} (otherwise refused, "
                  "exit code 2)",
                  kMaxNodesUnasked, human_duration(kMaxSecondsUnasked)));
  commands.push_back({run_app, [flags, &ctx] { return run(*flags, ctx); }});
}

}  // namespace vascsim
