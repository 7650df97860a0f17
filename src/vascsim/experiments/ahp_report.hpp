#pragma once
// Outputs of `vascsim ahp`: the weights (Table 1), the consistency of every matrix, the score table of all
// models (Table 3 with the per-indicator scores and where each came from) as CSV, Markdown and JSON, and a
// figure drawn by scripts/plot_ahp.py (Debian's matplotlib). Column meanings: docs/ahp.md.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vascsim/experiments/ahp_evaluation.hpp"

namespace vascsim::ahp {

/// One row per indicator: criterion and indicator weights, ours and the paper's, and the W_i used.
std::string weights_csv(const AhpReport& report);
/// One row per matrix (the criteria matrix, then each criterion's): n, lambda_max, CI, RI, CR.
std::string consistency_csv(const AhpReport& report);
/// One row per model: G (Eq. 40, empty if incomplete), the paper's printed G, the weight covered, and per
/// indicator its score and source (measured, rated, paper, missing).
std::string scores_csv(const AhpReport& report);
/// One row per model and indicator: score, source, measured value and unit, Table 2 level, W_i.
std::string indicator_scores_csv(const AhpReport& report);
/// The tables above as one Markdown page.
std::string markdown(const AhpReport& report);
nlohmann::json to_json(const AhpReport& report);

struct OutputOptions {
  std::filesystem::path out_dir;
  bool plot = true;
  std::string python = "/usr/bin/python3";
  /// Default: the bundled scripts/plot_ahp.py (core/bundled_files.hpp).
  std::filesystem::path plot_script;
};

struct Outputs {
  std::vector<std::filesystem::path> files;  ///< written, in order
  std::filesystem::path png;                 ///< empty if not plotted
  std::string plot_problem;                  ///< why there is no PNG (empty if plotted or not asked for)
};

/// Writes ahp_weights.csv, ahp_consistency.csv, ahp_scores.csv, ahp_indicator_scores.csv, ahp_report.md,
/// ahp_report.json and (plot) ahp_scores.png into out_dir. Throws InputError if a file cannot be written.
Outputs write_outputs(const AhpReport& report, const OutputOptions& options);

}  // namespace vascsim::ahp
