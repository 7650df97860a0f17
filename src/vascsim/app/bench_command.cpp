// `vascsim bench`: wall time per 1 ms step of a dynamic model at several resolutions and thread counts
// (docs/performance.md).

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <filesystem>

#include "vascsim/app/command.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/realtime_bench.hpp"
#include "vascsim/run/output_writer.hpp"

namespace vascsim {

namespace {

struct BenchFlags {
  RealtimeBenchOptions options;
  std::vector<std::string> outs;
  CLI::Option* threads = nullptr;
};

int bench(BenchFlags& flags, CliContext& ctx) {
  // Check the output names before minutes of timing.
  for (const auto& f : flags.outs) {
    const auto ext = std::filesystem::path(f).extension();
    if (ext != ".csv" && ext != ".json")
      throw InputError(
          fmt::format("bench: --out '{}' must end in .csv or .json (give --out twice for both)", f));
  }
  RealtimeBenchOptions opt = flags.options;
  if (flags.threads->count() == 0 && ctx.threads > 0) opt.threads = {ctx.threads};
  // Every configuration builds a Simulation, whose set-up log lines would bury the results.
  if (!ctx.verbose) spdlog::default_logger()->set_level(spdlog::level::warn);
  if (!ctx.quiet) opt.progress = [&ctx](const std::string& line) { ctx.err << line << std::endl; };
  const RealtimeBenchReport report = run_realtime_bench(opt);
  ctx.out << realtime_bench_table(report);
  for (const auto& f : flags.outs) {
    const std::filesystem::path path(f);
    const OutputWriter out(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."));
    if (path.extension() == ".csv")
      out.write_text(path.filename().string(), realtime_bench_csv(report));
    else
      out.write_json(path.filename().string(), realtime_bench_json(report));
    ctx.out << "wrote " << f << "\n";
  }
  return 0;
}

}  // namespace

void add_bench_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto flags = std::make_shared<BenchFlags>();
  RealtimeBenchOptions& o = flags->options;
  o.scene_path = "scenes/vein-indent.json";
  CLI::App* bench_app = app.add_subcommand(
      "bench", "Real-time benchmark: wall time per 1 ms step at several resolutions (docs/performance.md)");
  bench_app->add_option("scene", o.scene_path, "Scene JSON file with a tube geometry")->capture_default_str();
  bench_app->add_option("--model", o.model, "Dynamic model to time (e.g. xpbd or explicit)")
      ->capture_default_str();
  bench_app->add_option("--nodes", o.target_nodes, "Target node counts (the nearest tube resolution is used)")
      ->delimiter(',')
      ->capture_default_str();
  flags->threads =
      bench_app
          ->add_option("--threads", o.threads,
                       fmt::format("OpenMP thread counts, each 1 to {} (default 1,2; or -j N)", kMaxThreads))
          ->delimiter(',')
          ->check(CLI::Range(1, kMaxThreads));
  bench_app->add_option("--steps", o.steps, "Timed 1 ms steps per configuration")->capture_default_str();
  bench_app->add_option("--warmup", o.warmup_steps, "Untimed steps before them")->capture_default_str();
  bench_app->add_option("--set", o.overrides, "Override a scene key: path.to.key=value (repeatable)");
  bench_app->add_option("--out", flags->outs,
                        "Write FILE.csv or FILE.json (repeatable: --out a.csv --out a.json)");
  commands.push_back({bench_app, [flags, &ctx] { return bench(*flags, ctx); }});
}

}  // namespace vascsim
