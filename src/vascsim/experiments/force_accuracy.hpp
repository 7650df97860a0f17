#pragma once
// How accurate a scene's forces are expected to be, from the project's own measurements (data/calibration/
// force_accuracy.json, the table of docs/validation.md "Real-time resolutions: force error against node
// count", written by scripts/realtime_resolution_table.py --accuracy-table):
//  - the discretisation error of a vessel at a node count: a case of the table (the same cross-section,
//  loaded
//    the same way: a bonded indenter region or a tool, with the same local-fit basis) interpolated in
//    log(node count) between its two rows;
//  - models known to be far off at some settings: xpbd's force deficit when its per-substep stiffness ratio
//    q = (h c_p / spacing)^2 is large (docs/validation.md, "xpbd steady state against quasi_static").

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vascsim/scene/scene.hpp"

namespace vascsim {

struct AccuracyRow {
  double spacing_m = 0.0;
  double nodes = 0.0;
  double force_n = 0.0;
  double error = 0.0;  ///< force / reference force - 1
};

/// The error of a case's finest row against an independent solution (a mesh-converged FEM reference): the
/// table's errors are against that row, so a user needs both to know how far the force is from the continuum.
struct IndependentCheck {
  std::string reference;  ///< what it is and where its curve is, e.g. "CalculiX,
                          ///< validation/references/aorta-bent.csv"
  double error = 0.0;     ///< finest row's force / reference force - 1
  std::string where;      ///< the depths it was measured at, e.g. "0.5-2 mm of the 5 mm push"
};

struct AccuracyCase {
  std::string name, scene;
  /// The local fit's basis the rows were measured with ("linear", "quadratic", "quadratic_cube": the
  /// quadratic fit with the through-wall cube; the key "basis", "linear" when absent): a scene is compared
  /// with the cases of its own basis only (quasi_static fits curvature on walls, implicit does not;
  /// docs/model/00-design-decisions.md, decision 8).
  std::string basis = "linear";
  bool tool = false;  ///< loaded by a tool (obstacle) rather than a bonded region
  double outer_radius_m = 0.0, wall_thickness_m = 0.0;
  std::vector<AccuracyRow> rows;                ///< by node count, ascending
  std::optional<IndependentCheck> independent;  ///< the key "finest_row_against" of the case, when measured
};

/// A model whose force is known to fall short when its per-substep stiffness ratio is large.
struct SubstepStiffnessRule {
  std::string model;
  std::string substep_key;  ///< the key of the model's info() holding the substep, s
  double warn_above = 0.0;  ///< warn when q exceeds this
  std::string measured;     ///< the measurements to cite, one phrase
};

struct ForceAccuracyTable {
  std::filesystem::path file;
  std::string reference, measured, regenerate;
  std::vector<AccuracyCase> cases;
  std::vector<SubstepStiffnessRule> substep_rules;

  /// Throws InputError naming the file if it is missing or malformed.
  static ForceAccuracyTable read(const std::filesystem::path& file);
  /// data/calibration/force_accuracy.json of the source tree this binary was built from.
  static std::filesystem::path default_file();
};

/// The expected force error of a scene at `nodes` nodes.
struct AccuracyEstimate {
  const AccuracyCase* match = nullptr;  ///< null: no case of the table has this vessel and loading
  double error = 0.0;                   ///< interpolated (or the nearest row's outside the table)
  const AccuracyRow* below = nullptr;   ///< the rows it lies between (one of them null outside the table)
  const AccuracyRow* above = nullptr;
  double nodes = 0.0;   ///< the node count asked about
  bool graded = false;  ///< a graded lattice (geometry.refine): the table's uniform rows do not apply
  /// Without a match, on a vessel: the case closest to it (the same loading and fit first, then the nearest
  /// radius and wall thickness in log scale), for the user to compare with; null otherwise.
  const AccuracyCase* nearest = nullptr;
};

AccuracyEstimate estimate_accuracy(const ForceAccuracyTable& table, const Scene& scene, double nodes);

/// One line: the error, the rows it comes from and what the error is measured against (and, when the case has
/// one, how far that is from the independent reference).
std::string describe_accuracy(const ForceAccuracyTable& table, const AccuracyEstimate& e);

/// q = (h c_p / spacing)^2 with c_p = sqrt((lambda + 2 mu) / rho), the per-substep stiffness ratio.
double substep_stiffness_ratio(double substep_s, const Material& material, double spacing_m);

}  // namespace vascsim
