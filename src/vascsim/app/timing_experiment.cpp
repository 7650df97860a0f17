// `vascsim experiment timing`: time per step and frames per second against node count for several models (the
// paper's Figs. 11-12; experiments/timing_sweep.hpp). Every point can run as its own process (--point) and a
// folder of points is merged into one table and figure (--merge): docs/replicate.md.

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <filesystem>
#include <fstream>

#include "vascsim/app/command.hpp"
#include "vascsim/app/progress.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/machine_info.hpp"
#include "vascsim/experiments/measured_indicators.hpp"
#include "vascsim/experiments/plot_script.hpp"
#include "vascsim/experiments/timing_sweep.hpp"
#include "vascsim/run/output_writer.hpp"

namespace vascsim {

namespace {

namespace fs = std::filesystem;

struct TimingFlags {
  TimingSweepOptions options;
  std::string out = "out/timing", point, force_errors;
  bool merge_only = false, reuse = false, no_plot = false;
};

void run_point(const TimingFlags& f, const std::string& model, int target, Progress* progress, int index,
               int total, CliContext& ctx) {
  const fs::path file = fs::path(f.out) / "points" / timing_point_file(model, target);
  if (f.reuse && fs::exists(file)) return;
  TimingSweepOptions o = f.options;
  if (progress)
    o.on_step = [&](int step, int steps) {
      progress->update(index, total, fmt::format("{} at {} nodes: step {}/{}", model, target, step, steps));
    };
  const TimingPoint p = run_timing_point(o, model, target);
  const OutputWriter out(file.parent_path());
  out.write_json(file.filename().string(), timing_point_json(p));
  if (!progress) ctx.out << timing_table({p});
}

int merge(const TimingFlags& f, CliContext& ctx) {
  const std::vector<TimingPoint> points = merge_timing_points(f.out, f.options.models);
  const OutputWriter out(f.out);
  out.write_text("timing.csv", timing_csv(points));
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& p : points) rows.push_back(timing_point_json(p));
  out.write_json("timing.json", {{"experiment", "timing"},
                                 {"scene", f.options.scene_path},
                                 {"merged_on", machine_info()},
                                 {"points", rows}});
  nlohmann::json rms = nullptr;
  if (!f.force_errors.empty()) {
    std::ifstream in(f.force_errors);
    rms = nlohmann::json::parse(in, nullptr, false);
    if (!in || rms.is_discarded() || !rms.contains("models"))
      throw InputError(fmt::format("timing: --force-errors {}: not an rms_error.json", f.force_errors));
  }
  out.write_json(
      "ahp_measurements.json",
      ahp_measurements(points, rms,
                       fmt::format("vascsim experiment timing {} (merged {}){}", f.options.scene_path,
                                   utc_now(), f.force_errors.empty() ? "" : "; " + f.force_errors)));
  ctx.out << timing_table(points);
  ctx.out << fmt::format("wrote {}, {}, {}\n", (fs::path(f.out) / "timing.csv").string(),
                         (fs::path(f.out) / "timing.json").string(),
                         (fs::path(f.out) / "ahp_measurements.json").string());
  if (f.no_plot) return 0;
  const fs::path png = fs::path(f.out) / "timing.png";
  const PlotOutcome plot =
      run_plot_script(bundled_script("plot_timing.py"),
                      {(fs::path(f.out) / "timing.json").string(), "--out", png.string()}, png);
  if (plot.problem.empty())
    ctx.out << "wrote " << png.string() << "\n";
  else
    ctx.out << "warning: no plot: " << plot.problem << "\n";
  return 0;
}

int timing(TimingFlags& f, CliContext& ctx) {
  if (ctx.threads > 0) f.options.threads = ctx.threads;
  if (!ctx.verbose) spdlog::default_logger()->set_level(spdlog::level::warn);
  if (f.merge_only) return merge(f, ctx);
  if (!f.point.empty()) {  // one point, as its own job: MODEL:NODES
    const auto colon = f.point.find(':');
    if (colon == std::string::npos)
      throw InputError(fmt::format("timing: --point '{}' must be MODEL:NODES", f.point));
    int nodes = 0;
    try {
      nodes = std::stoi(f.point.substr(colon + 1));
    } catch (const std::exception&) {
      throw InputError(fmt::format("timing: --point '{}' must be MODEL:NODES", f.point));
    }
    run_point(f, f.point.substr(0, colon), nodes, nullptr, 0, 1, ctx);
    return 0;
  }
  const int total = static_cast<int>(f.options.models.size() * f.options.target_nodes.size());
  Progress progress(ctx.err, ctx.err_is_terminal(), "timing", ctx.quiet);
  int index = 0;
  for (const auto& model : f.options.models)
    for (int target : f.options.target_nodes)
      run_point(f, model, target, ctx.quiet ? nullptr : &progress, index++, total, ctx);
  progress.finish();
  return merge(f, ctx);
}

}  // namespace

void add_timing_experiment(CLI::App& experiment, CliContext& ctx, std::vector<Command>& commands) {
  auto f = std::make_shared<TimingFlags>();
  TimingSweepOptions& o = f->options;
  CLI::App* app = experiment.add_subcommand(
      "timing",
      "Time per 1 ms step and frames per second against node count for several models (the paper's "
      "Figs. 11-12): OUT/points/*.json, OUT/timing.csv, .json and .png");
  app->add_option("scene", o.scene_path, "Scene JSON file with a tube geometry")->capture_default_str();
  app->add_option("--models", o.models, "Dynamic models to time")->delimiter(',')->capture_default_str();
  app->add_option("--nodes", o.target_nodes, "Target node counts (the nearest tube resolution is used)")
      ->delimiter(',')
      ->capture_default_str();
  app->add_option("--steps", o.steps, "Timed 1 ms steps per point (the median is reported)")
      ->capture_default_str();
  app->add_option("--warmup", o.warmup_steps, "Untimed steps before them")->capture_default_str();
  app->add_option("--set", o.overrides, "Override a scene key: path.to.key=value (repeatable)");
  app->add_option("--out", f->out, "Output folder")->capture_default_str();
  app->add_option("--point", f->point,
                  "Run one point MODEL:NODES into OUT/points/ and stop (a job of a fanned-out sweep)");
  app->add_flag("--merge", f->merge_only, "Only merge OUT/points/*.json into timing.csv, .json and .png");
  app->add_flag("--reuse", f->reuse, "Skip points whose OUT/points/<model>-<nodes>.json exists");
  app->add_flag("--no-plot", f->no_plot, "No figure");
  app->add_option(
      "--force-errors", f->force_errors,
      "rms_error.json of `experiment force-displacement --models`: adds each model's force error (I7) to "
      "OUT/ahp_measurements.json (for `vascsim ahp --measurements`)");
  commands.push_back({app, [f, &ctx] { return timing(*f, ctx); }});
}

}  // namespace vascsim
