// `vascsim soak SCENE`: the soak test of docs/reliability.md (run/soak.hpp): a realtime haptic session with a
// wandering tool for --seconds, then soak.json and soak.md.

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cmath>

#include "vascsim/app/command.hpp"
#include "vascsim/app/progress.hpp"
#include "vascsim/run/soak.hpp"

namespace vascsim {

namespace {

struct SoakFlags {
  std::string scene, out;
  std::vector<std::string> sets;
  SoakOptions options;
};

int soak(SoakFlags& flags, CliContext& ctx) {
  const Scene scene = load_scene(flags.scene, flags.sets);
  flags.options.out_dir =
      flags.out.empty() ? std::filesystem::path("out") / "soak" : std::filesystem::path(flags.out);
  spdlog::info("soak of '{}' ({}): {} s realtime, seed {}, output {}", scene.name, scene.file,
               flags.options.seconds, flags.options.bounds.seed, flags.options.out_dir.string());
  Progress progress(ctx.err, ctx.err_is_terminal(), scene.name, ctx.quiet);
  flags.options.on_progress = [&](double done, double total) {
    progress.update(static_cast<int>(std::lround(1000.0 * done / total)), 1000,
                    fmt::format("soak t = {:.0f} of {:.0f} s", done, total));
  };
  const nlohmann::json r = run_soak(scene, flags.options);
  progress.finish();
  const auto& m = r["memory"];
  ctx.out << fmt::format(
      "{}: {} ticks at {:.1f} Hz, {} frames; NaN events {}, clamp events {}, max force sent {:.3g} N; jitter "
      "p50/p99/max {:.3f}/{:.3f}/{:.3f} ms; memory growth after warm-up {:.1f} MiB ({:.1f} MiB/h); wrote "
      "{}\n",
      scene.name, r["ticks"].get<std::uint64_t>(), r["achieved_rate_hz"].get<double>(),
      r["simulation_steps"].get<std::uint64_t>(), r["nan_events"].get<std::uint64_t>(),
      r["clamp_events"].get<std::uint64_t>(), r["max_force_sent_n"].get<double>(),
      r["jitter_ms"]["p50"].get<double>(), r["jitter_ms"]["p99"].get<double>(),
      r["jitter_ms"]["max"].get<double>(), m.value("growth_after_warmup_mib", 0.0),
      m.value("slope_mib_per_hour", 0.0), (flags.options.out_dir / "soak.json").string());
  return 0;
}

}  // namespace

void add_soak_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto flags = std::make_shared<SoakFlags>();
  CLI::App* cmd = app.add_subcommand(
      "soak",
      "Soak test: a realtime haptic session with random but bounded tool motion (docs/reliability.md)");
  cmd->add_option("scene", flags->scene, "Real-time scene JSON with a haptics block")->required();
  cmd->add_option("--set", flags->sets, "Override a scene key: path.to.key=value (repeatable)");
  cmd->add_option("--out", flags->out, "Output folder (default: out/soak)");
  cmd->add_option("--seconds", flags->options.seconds, "Session length, s (wall clock)")
      ->check(CLI::Range(1e-3, 1e6))
      ->capture_default_str();
  cmd->add_option("--seed", flags->options.bounds.seed, "Seed of the tool's waypoints")
      ->capture_default_str();
  cmd->add_option("--depth-m", flags->options.bounds.depth_m, "Push depth along the tool, 0 to this, m")
      ->check(CLI::Range(0.0, 0.1))
      ->capture_default_str();
  cmd->add_option("--lateral-m", flags->options.bounds.lateral_m, "Motion across the tool, +- this, m")
      ->check(CLI::Range(0.0, 0.1))
      ->capture_default_str();
  cmd->add_option("--segment-s", flags->options.bounds.segment_s, "Time between waypoints, s")
      ->check(CLI::Range(1e-3, 1e3))
      ->capture_default_str();
  cmd->add_option("--rss-interval-s", flags->options.rss_interval_s, "Resident memory sampled this often, s")
      ->check(CLI::Range(1e-2, 1e3))
      ->capture_default_str();
  commands.push_back({cmd, [flags, &ctx] { return soak(*flags, ctx); }});
}

}  // namespace vascsim
