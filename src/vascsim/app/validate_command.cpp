// `vascsim validate ...`: validation studies against analytic references (the cantilever table T9, the MLS
// surface map's T11/T15 on scene bodies).

#include <fmt/format.h>
#include <filesystem>

#include "vascsim/app/command.hpp"
#include "vascsim/app/progress.hpp"
#include "vascsim/experiments/cantilever.hpp"
#include "vascsim/experiments/mls_validation.hpp"
#include "vascsim/run/output_writer.hpp"

namespace vascsim {

namespace {

struct CantileverFlags {
  std::string out;
  std::vector<int> sizes = {2, 3, 4, 6};
};

int validate_cantilever(const CantileverFlags& flags, CliContext& ctx) {
  const OutputWriter out(flags.out.empty() ? std::filesystem::path("out/cantilever-table")
                                           : std::filesystem::path(flags.out));
  CsvTable csv =
      out.table("cantilever-table.csv", {"configuration", "n", "nodes", "tip_deflection_m", "reference_m",
                                         "ratio", "newton_iterations", "residual", "seconds"});
  std::string md = "| configuration |";
  for (int n : flags.sizes) md += fmt::format(" n = {} |", n);
  md += "\n|---|";
  for (std::size_t i = 0; i < flags.sizes.size(); ++i) md += "---|";
  md += "\n";
  const std::vector<CantileverConfiguration> rows = cantilever_table_configurations();
  Progress progress(ctx.err, ctx.err_is_terminal(), "cantilever", ctx.quiet);
  const int total = static_cast<int>(rows.size() * flags.sizes.size());
  int done = 0;
  for (const CantileverConfiguration& row : rows) {
    md += "| " + row.label + " |";
    for (int n : flags.sizes) {
      CantileverCase c = row.base;
      c.cells_across = n;
      const CantileverResult r = run_cantilever(c);
      csv.add_row(fmt::format("\"{}\",{},{},{:.9g},{:.9g},{:.6f},{},{:.3g},{:.3f}", row.label, n, r.nodes,
                              r.tip_deflection_m, r.reference_m, r.ratio, r.newton_iterations, r.residual,
                              r.seconds));
      md += fmt::format(" {:.3f} |", r.ratio);
      progress.update(++done, total, fmt::format("{} n={}: ratio {:.4f}", row.label, n, r.ratio));
    }
    md += "\n";
  }
  progress.finish();
  out.write_text("cantilever-table.md", md);
  ctx.out << "delta / delta_Timoshenko (tip load, L/b = 10, clamp = 3 node layers, quasi-static):\n\n" << md;
  ctx.out << fmt::format("\nwrote {} and {}\n", out.path("cantilever-table.csv").string(),
                         out.path("cantilever-table.md").string());
  return 0;
}

struct MlsFlags {
  std::vector<std::string> scenes, sets;
  double tight_factor = 1.0;
  std::string out;
};

int validate_mls_command(const MlsFlags& flags, CliContext& ctx) {
  const nlohmann::json rows = validate_mls(flags.scenes, flags.sets, flags.tight_factor);
  const OutputWriter out(flags.out.empty() ? std::filesystem::path("out/mls-validation")
                                           : std::filesystem::path(flags.out));
  const std::string table = mls_validation_table(rows);
  out.write_json("mls-validation.json", rows);
  out.write_text("mls-validation.md", table);
  ctx.out << table << "wrote " << out.path("mls-validation.json").string() << " and mls-validation.md\n";
  bool all = true;
  for (const auto& r : rows) all = all && r["t11_pass"].get<bool>();
  return all ? 0 : 1;
}

}  // namespace

void add_validate_commands(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  CLI::App* validate = app.add_subcommand("validate", "Validation studies against analytic references");
  validate->require_subcommand(1);

  auto cant = std::make_shared<CantileverFlags>();
  CLI::App* cant_app =
      validate->add_subcommand("cantilever", "T9: cantilever convergence table (docs/validation.md)");
  cant_app->add_option("--out", cant->out, "Output folder (default: out/cantilever-table)");
  cant_app->add_option("--sizes", cant->sizes, "Cells across the beam, n = b / Delta")
      ->delimiter(',')
      ->check(CLI::Range(1, 16));
  commands.push_back({cant_app, [cant, &ctx] { return validate_cantilever(*cant, ctx); }});

  auto mls = std::make_shared<MlsFlags>();
  CLI::App* mls_app = validate->add_subcommand(
      "mls", "T11/T15: the MLS surface map of each scene's body (docs/validation.md)");
  mls_app->add_option("scenes", mls->scenes, "Scene JSON files")->required();
  mls_app->add_option("--set", mls->sets, "Override a key in every scene: path.to.key=value (repeatable)");
  mls_app->add_option("--tight-factor", mls->tight_factor, "Support radius factor for the T15 guard check")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 5.0));
  mls_app->add_option("--out", mls->out, "Output folder (default: out/mls-validation)");
  commands.push_back({mls_app, [mls, &ctx] { return validate_mls_command(*mls, ctx); }});
}

}  // namespace vascsim
