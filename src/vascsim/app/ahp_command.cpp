// `vascsim ahp`: the paper's analytic hierarchy process (Tables 1-3, Eq. 40; docs/ahp.md).

#include <filesystem>

#include "vascsim/app/command.hpp"
#include "vascsim/experiments/ahp_evaluation.hpp"
#include "vascsim/experiments/ahp_report.hpp"

namespace vascsim {

namespace {

struct AhpFlags {
  std::string hierarchy, bands, ratings, measurements, out = "out/ahp";
  bool no_plot = false, paper_weights = false;
};

int ahp_command(const AhpFlags& f, CliContext& ctx) {
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
  ctx.out << ahp::markdown(report) << "\n";
  for (const auto& p : written.files) ctx.out << "wrote " << p.string() << "\n";
  if (!written.png.empty()) ctx.out << "wrote " << written.png.string() << "\n";
  if (!written.plot_problem.empty()) ctx.out << "warning: no plot: " << written.plot_problem << "\n";
  return 0;
}

}  // namespace

void add_ahp_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto flags = std::make_shared<AhpFlags>();
  CLI::App* ahp_app = app.add_subcommand(
      "ahp",
      "The paper's AHP evaluation (Tables 1-3, Eq. 40): weights and consistency of the pairwise matrices, "
      "the "
      "score table of all models and a figure (docs/ahp.md); default inputs: the bundled data/ahp files");
  ahp_app->add_option("--hierarchy", flags->hierarchy,
                      "Hierarchy with pairwise matrices (default: paper-hierarchy.json)");
  ahp_app->add_option("--bands", flags->bands, "Evaluation standard, Table 2 (default: paper-bands.json)");
  ahp_app->add_option("--ratings", flags->ratings,
                      "Indicator ratings per model (default: paper-ratings.json)");
  ahp_app->add_option("--measurements", flags->measurements,
                      "Measured figures per model (data/ahp/measurements.schema.json; default: none)");
  ahp_app->add_option("--out", flags->out, "Output folder")->capture_default_str();
  ahp_app->add_flag("--no-plot", flags->no_plot, "Write the tables only (no matplotlib call)");
  ahp_app->add_flag("--paper-weights", flags->paper_weights,
                    "Use Table 1's printed W_i in Eq. 40 instead of the weights computed from the matrices");
  commands.push_back({ahp_app, [flags, &ctx] { return ahp_command(*flags, ctx); }});
}

}  // namespace vascsim
