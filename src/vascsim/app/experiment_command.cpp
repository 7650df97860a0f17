// `vascsim experiment ...`: the paper's experiments, one command each.

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <filesystem>
#include <memory>

#include "vascsim/app/command.hpp"
#include "vascsim/app/progress.hpp"
#include "vascsim/app/step_status.hpp"
#include "vascsim/experiments/force_displacement.hpp"
#include "vascsim/experiments/model_comparison.hpp"

namespace vascsim {

namespace {

struct ForceDisplacementFlags {
  std::string scene, out, tool, reference = "quasi_static";
  std::vector<std::string> sets, models;
  bool no_plot = false, reuse = false;
};

// --models: every model on the scene, against the reference (model_comparison.hpp).
int compare_models(const ForceDisplacementFlags& flags, CliContext& ctx) {
  const Scene scene =
      load_scene(flags.scene, flags.sets);  // checks the scene and the overrides once, up front
  ModelComparisonOptions opt;
  opt.out_dir = flags.out.empty() ? std::filesystem::path("out") / (scene.name + "-models")
                                  : std::filesystem::path(flags.out);
  opt.models = flags.models;
  opt.reference = flags.reference;
  opt.overrides = flags.sets;
  opt.tool = flags.tool;
  opt.reuse = flags.reuse;
  opt.plot = !flags.no_plot;
  std::unique_ptr<Progress> progress;
  std::string current;
  opt.progress = [&](const std::string& line) {
    if (progress) progress->finish();
    progress.reset();
    if (!ctx.quiet) ctx.err << line << std::endl;
  };
  opt.on_step = [&](const std::string& model, const StepRecord& r, int total) {
    if (!progress || current != model)
      progress =
          std::make_unique<Progress>(ctx.err, ctx.err_is_terminal(), scene.name + " " + model, ctx.quiet),
      current = model;
    progress->update(r.step, total, step_status(model, r));
  };
  const ModelComparisonResult res = run_model_comparison(flags.scene, opt);
  if (progress) progress->finish();
  ctx.out << model_comparison_table(res);
  ctx.out << "wrote " << res.csv.string() << ", " << res.rms_csv.string() << ", " << res.rms_json.string()
          << "\n";
  if (!res.png.empty()) ctx.out << "wrote " << res.png.string() << "\n";
  if (!res.plot_problem.empty()) ctx.out << "warning: no plot: " << res.plot_problem << "\n";
  return 0;
}

int force_displacement(const ForceDisplacementFlags& flags, CliContext& ctx) {
  if (!flags.models.empty()) return compare_models(flags, ctx);
  const Scene scene = load_scene(flags.scene, flags.sets);
  ForceDisplacementOptions opt;
  opt.out_dir = flags.out.empty() ? std::filesystem::path("out") / (scene.name + "-force-displacement")
                                  : std::filesystem::path(flags.out);
  opt.tool = flags.tool;
  opt.plot = !flags.no_plot;
  spdlog::info("force-displacement: scene '{}' ({}), model {}, output {}", scene.name, scene.file,
               scene.model, opt.out_dir.string());
  Progress progress(ctx.err, ctx.err_is_terminal(), scene.name, ctx.quiet);
  opt.on_step = [&](const StepRecord& r, int total) {
    progress.update(r.step, total, step_status(scene.model, r));
  };
  const ForceDisplacementResult res = run_force_displacement(scene, opt);
  progress.finish();
  const auto& rows = res.summary["force_displacement"]["rows"];
  const auto& last = rows.back();
  ctx.out << fmt::format("{}: tool '{}' at {:.4g} mm: {:.4g} mN ({} steps, model {}); wrote {}\n", scene.name,
                         res.summary["force_displacement"]["tool"].get<std::string>(),
                         last["displacement_m"].get<double>() * 1e3, last["force_n"].get<double>() * 1e3,
                         rows.size() - 1, scene.model, res.csv.string());
  if (!res.png.empty()) ctx.out << "wrote " << res.png.string() << "\n";
  if (!res.plot_problem.empty()) ctx.out << "warning: no plot: " << res.plot_problem << "\n";
  if (res.summary["unconverged_steps"].get<int>() > 0)
    ctx.out << fmt::format("warning: {} load steps did not converge (see summary.json)\n",
                           res.summary["unconverged_steps"].get<int>());
  return 0;
}

}  // namespace

void add_experiment_commands(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  CLI::App* experiment = app.add_subcommand("experiment", "The paper's experiments, one command each");
  experiment->require_subcommand(1);
  auto fd = std::make_shared<ForceDisplacementFlags>();
  CLI::App* fd_app = experiment->add_subcommand(
      "force-displacement",
      "A tool (catheter) presses the vessel in displacement steps: force_displacement.csv "
      "and .png (the paper's Fig. 10: scenes/hand-dorsal-vein-catheter.json)");
  fd_app->add_option("scene", fd->scene, "Scene JSON file with a moving tool in 'obstacles'")->required();
  fd_app->add_option("--set", fd->sets,
                     "Override a scene key: path.to.key=value (repeatable), e.g. model=xpbd");
  fd_app->add_option("--out", fd->out, "Output folder (default: out/<scene name>-force-displacement)");
  fd_app->add_option("--tool", fd->tool, "The obstacle that presses (default: the scene's only obstacle)");
  fd_app->add_flag("--no-plot", fd->no_plot, "Write the CSV only (no matplotlib call)");
  fd_app
      ->add_option("--models", fd->models,
                   "Compare models: run each (OUT/<model>/) and write every curve, the RMS error against the "
                   "reference and one figure (e.g. implicit,xpbd,mass_spring)")
      ->delimiter(',');
  fd_app->add_option("--reference", fd->reference, "With --models: the reference model")
      ->capture_default_str();
  fd_app->add_flag(
      "--reuse", fd->reuse,
      "With --models: read a model's finished OUT/<model>/summary.json instead of running it (merge "
      "independent runs)");
  commands.push_back({fd_app, [fd, &ctx] { return force_displacement(*fd, ctx); }});
  add_timing_experiment(*experiment, ctx, commands);
}

}  // namespace vascsim
