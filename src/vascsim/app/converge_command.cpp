// `vascsim converge SCENE.json`: how accurate the scene is at its own resolution. Runs it at coarser spacings
// (and optionally one finer), extrapolates every output with the observed order and reports the estimated
// discretisation error with its bound, or why the sequence gives none (run/convergence_study.hpp;
// docs/convergence.md).

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "vascsim/app/command.hpp"
#include "vascsim/app/progress.hpp"
#include "vascsim/app/run_limits.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/plot_script.hpp"
#include "vascsim/run/convergence_study.hpp"

namespace vascsim {

namespace {

struct ConvergeFlags {
  std::string scene, out, target;
  std::vector<std::string> sets;
  double ratio = std::sqrt(2.0);
  int coarser = 2;
  bool finer = false, yes = false, no_plot = false;
};

// "2%" or "0.02" as a fraction; a bare number of 1 or more is ambiguous and refused.
double parse_target(const std::string& text) {
  if (text.empty()) return 0.0;
  std::string number = text;
  const bool percent = !number.empty() && number.back() == '%';
  if (percent) number.pop_back();
  double value = 0.0;
  try {
    std::size_t used = 0;
    value = std::stod(number, &used);
    if (used != number.size()) throw std::invalid_argument(number);
  } catch (const std::exception&) {
    throw InputError(
        fmt::format("--target '{}': write a relative error as a percentage (2%) or a fraction (0.02)", text));
  }
  if (percent) value /= 100.0;
  if (!(value > 0.0) || value >= 1.0)
    throw InputError(fmt::format("--target '{}': a relative error between 0 and 100 % (2% or 0.02)", text));
  return value;
}

std::string pct(double fraction) {
  return fmt::format("{:+.2f} %", 100.0 * fraction);
}

// "3-7" or "5" for a sorted list of steps, runs joined with commas.
std::string step_ranges(const std::vector<const ConvergenceOutput*>& rows) {
  std::string s;
  for (std::size_t i = 0; i < rows.size();) {
    std::size_t j = i;
    while (j + 1 < rows.size() && rows[j + 1]->step == rows[j]->step + 1) ++j;
    if (!s.empty()) s += ", ";
    s += rows[i]->step == rows[j]->step ? fmt::format("{}", rows[i]->step)
                                        : fmt::format("{}-{}", rows[i]->step, rows[j]->step);
    i = j + 1;
  }
  return s;
}

std::string where(const ConvergenceOutput& o) {
  if (o.tool_displacement_m >= 0.0)
    return fmt::format("step {}, tool at {:.3g} mm", o.step, o.tool_displacement_m * 1e3);
  return fmt::format("step {}, load factor {:.3g}", o.step, o.load_factor);
}

void report_quantity(const ConvergenceResult& result, const std::string& quantity, double target,
                     CliContext& ctx) {
  std::vector<const ConvergenceOutput*> rows;
  for (const ConvergenceOutput& o : result.outputs)
    if (o.quantity == quantity) rows.push_back(&o);
  if (rows.empty()) return;
  const ConvergenceOutput& last = *rows.back();
  const std::size_t user = static_cast<std::size_t>(result.user_level);
  ctx.out << fmt::format("{} ({}):\n", quantity, last.unit);
  if (last.status == "extrapolated")
    ctx.out << fmt::format(
        "  last step ({}): {:.6g} at the scene's spacing, extrapolated {:.6g} (observed order {:.2f}): "
        "estimated error {}, |error| <= {:.2f} % (GCI)\n",
        where(last), last.values[user], last.estimate.extrapolated, last.estimate.order, pct(last.user_error),
        100.0 * last.user_bound);
  else
    ctx.out << fmt::format("  last step ({}): no estimate ({})\n", where(last), last.status);
  std::map<std::string, std::vector<const ConvergenceOutput*>> by_status;
  for (const ConvergenceOutput* o : rows) by_status[o->status].push_back(o);
  const ConvergenceOutput* worst = nullptr;
  if (auto it = by_status.find("extrapolated"); it != by_status.end()) {
    double lo = 1e300, hi = -1e300;
    for (const ConvergenceOutput* o : it->second) {
      lo = std::min(lo, o->user_error);
      hi = std::max(hi, o->user_error);
      if (!worst || o->user_bound > worst->user_bound) worst = o;
    }
    ctx.out << fmt::format("  steps {}: estimated error {} to {}, the largest bound {:.2f} % (step {})\n",
                           step_ranges(it->second), pct(lo), pct(hi), 100.0 * worst->user_bound, worst->step);
  }
  static const std::map<std::string, std::string> why = {
      {"contact not resolved",
       "the tool's contact spans under 1.4 node spacings at some level (the force "
       "depends on where the nodes fall there)"},
      {"oscillating", "not in the asymptotic range: the values go up and down with the spacing"},
      {"order out of range", fmt::format("not in the asymptotic range: observed order outside [{}, {}]",
                                         kMinObservedOrder, kMaxObservedOrder)},
      {"orders disagree",
       "not in the asymptotic range: the finest and the coarsest three levels give orders "
       "that differ by more than half"},
      {"not converged", "a level's solve did not converge"},
      {"zero", "no load yet"},
      {"exact", "the same value at every spacing"}};
  for (const auto& [status, list] : by_status) {
    if (status == "extrapolated") continue;
    const auto w = why.find(status);
    ctx.out << fmt::format("  steps {}: no estimate: {}\n", step_ranges(list),
                           w != why.end() ? w->second : status);
  }
  if (target > 0.0 && worst) {
    if (worst->user_bound <= target)
      ctx.out << fmt::format(
          "  target {:.2g} %: met at the scene's spacing (every estimated step within {:.2f} %)\n",
          100.0 * target, 100.0 * worst->user_bound);
    else {
      double spacing = 1e300;
      for (const ConvergenceOutput* o : by_status["extrapolated"])
        if (o->user_bound > target)
          spacing = std::min(spacing, spacing_for_target(result, *o, target / kGciSafetyFactor));
      ctx.out << fmt::format(
          "  target {:.2g} %: a node spacing of about {:.4g} mm (now {:.4g} mm) brings every "
          "estimated step's bound under it (error falling as h^p)\n",
          100.0 * target, spacing * 1e3, result.levels[user].spacing_m * 1e3);
    }
  }
}

int converge(const ConvergeFlags& flags, CliContext& ctx) {
  const double target = parse_target(flags.target);
  const Scene scene = load_scene(flags.scene, flags.sets);
  ConvergenceOptions options;
  options.out_dir = flags.out.empty() ? std::filesystem::path("out") / (scene.name + "-converge")
                                      : std::filesystem::path(flags.out);
  options.ratio = flags.ratio;
  options.coarser_levels = flags.coarser;
  options.finer = flags.finer;
  options.target = target;
  options.checks = node_limit(scene, flags.yes);
  Progress progress(ctx.err, ctx.err_is_terminal(), scene.name, ctx.quiet);
  int level = 0, levels = 0;
  std::string label;
  options.on_level = [&](int index, int count, double factor, const std::string& what) {
    level = index;
    levels = count;
    label = fmt::format("level {} of {} ({})", index + 1, count, what);
    (void)factor;
    // The scene's own level logs as `run` would; the others only their errors unless -v (their warnings, e.g.
    // a contact the coarser lattice does not resolve, are the study's business and in their summary.json).
    if (!ctx.verbose)
      spdlog::set_level(index == 0 ? (ctx.quiet ? spdlog::level::warn : spdlog::level::info)
                                   : spdlog::level::err);
  };
  options.on_step = [&](const StepRecord& r, int total) {
    progress.update(level * total + r.step, levels * total,
                    fmt::format("{}, step {} of {}", label, r.step, total));
  };
  const spdlog::level::level_enum log_level = spdlog::get_level();
  const ConvergenceResult result = run_convergence_study(scene, options);
  spdlog::set_level(log_level);
  progress.finish();
  if (!result.refused.empty()) {
    ctx.out << fmt::format("{}: NO ESTIMATE: {}\nwrote {}\n", scene.name, result.refused,
                           (options.out_dir / "convergence.json").string());
    return 0;
  }
  std::string spacings, nodes;
  double seconds = 0.0;
  for (const ConvergenceLevel& l : result.levels) {
    spacings +=
        fmt::format("{}{:.4g}{}", spacings.empty() ? "" : " / ", l.spacing_m * 1e3, l.user ? "*" : "");
    nodes += fmt::format("{}{}", nodes.empty() ? "" : " / ", l.nodes);
    seconds += l.seconds;
  }
  const ConvergenceLevel& mine = result.levels[static_cast<std::size_t>(result.user_level)];
  const int layers = mine.signature.wall_layers;
  ctx.out << fmt::format("{}: {} levels, node spacing{} {} mm (* the scene's), {} nodes{}, {:.0f} s\n",
                         scene.name, result.levels.size(), layers > 0 ? " along the wall" : "", spacings,
                         nodes, layers > 0 ? fmt::format(", {} layers through the wall", layers) : "",
                         seconds);
  std::vector<std::string> seen;
  for (const ConvergenceOutput& o : result.outputs)
    if (std::find(seen.begin(), seen.end(), o.quantity) == seen.end()) seen.push_back(o.quantity);
  for (const std::string& q : seen) report_quantity(result, q, target, ctx);
  const std::filesystem::path csv = options.out_dir / "convergence.csv";
  ctx.out << fmt::format("wrote {}, {}\n", csv.string(), (options.out_dir / "convergence.json").string());
  if (flags.no_plot) return 0;
  const std::filesystem::path png = options.out_dir / "convergence.png";
  const PlotOutcome plot =
      run_plot_script(bundled_script("plot_convergence.py"),
                      {(options.out_dir / "convergence.json").string(), "--out", png.string()}, png);
  if (plot.problem.empty())
    ctx.out << "wrote " << png.string() << "\n";
  else
    ctx.out << "warning: no plot: " << plot.problem << "\n";
  return 0;
}

}  // namespace

void add_converge_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto flags = std::make_shared<ConvergeFlags>();
  CLI::App* sub = app.add_subcommand(
      "converge",
      "Estimate a scene's discretisation error: run it at coarser node spacings (and optionally one finer), "
      "extrapolate each output with the observed order and report its error and bound (docs/convergence.md)");
  sub->add_option("scene", flags->scene,
                  "Scene JSON file (docs/scene-format.md); a headless scene with load steps")
      ->required();
  sub->add_option("--set", flags->sets, "Override a scene key: path.to.key=value (repeatable)");
  sub->add_option("--out", flags->out, "Output folder (default: out/<scene name>-converge)");
  sub->add_option("--ratio", flags->ratio, "Spacing of each level over the next finer one (default: sqrt(2))")
      ->check(CLI::Range(1.05, 4.0));
  sub->add_option("--coarser", flags->coarser, "Levels coarser than the scene's (default: 2)")
      ->check(CLI::Range(1, 4));
  sub->add_flag(
      "--finer", flags->finer,
      "Also one level finer than the scene's (about ratio^2-ratio^3 times its cost): a second estimate "
      "of the order that checks the first");
  sub->add_option(
      "--target", flags->target,
      "A relative error to reach, e.g. 2% or 0.02: reports the spacing that brings the bound under it");
  sub->add_flag("--no-plot", flags->no_plot, "Write the CSV and JSON only, no convergence.png");
  sub->add_flag("--yes", flags->yes, fmt::format("Allow levels of more than {} nodes", kMaxNodesUnasked));
  commands.push_back({sub, [flags, &ctx] { return converge(*flags, ctx); }});
}

}  // namespace vascsim
