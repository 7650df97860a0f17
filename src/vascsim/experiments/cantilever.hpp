#pragma once
// The cantilever convergence study of docs/validation.md T9: a square beam, L/b = 10, clamped by the node
// layers at x <= 0, loaded at the tip face by a small transverse force spread by area, solved
// quasi-statically, compared with the Timoshenko deflection (experiments/timoshenko.hpp).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace vascsim {

struct CantileverCase {
  int cells_across = 4;  ///< n = b / Delta
  double poisson_ratio = 0.45;
  double support_radius_factor = 2.0;
  int min_neighbours =
      12;  ///< K_min of the support-radius guard (docs/model/00-design-decisions.md, decision 7)
  double stabilizer_alpha = 0.1;
  std::string stabilizer_fit = "basis";  ///< or "quadratic" (energy.stabilizer_fit)
  std::string volume = "tet_partition";  ///< or "mueller_kernel"
  std::string strain = "green";          ///< or "mueller_no_half"
  double deflection_fraction = 1e-4;     ///< target delta_T / L (small: the linear regime)
};

struct CantileverResult {
  double tip_deflection_m = 0.0;
  double reference_m = 0.0;
  double ratio = 0.0;
  int nodes = 0;
  int newton_iterations = 0;
  double residual = 0.0;
  double seconds = 0.0;
};

/// The scene document of one case (also the shape of scenes/cantilever.json).
nlohmann::json cantilever_scene(const CantileverCase& c);

/// Runs one case (quasi-static, one load step).
CantileverResult run_cantilever(const CantileverCase& c);

/// One row of docs/validation.md's cantilever table: a label and the case (cells_across is set per column).
struct CantileverConfiguration {
  std::string label;
  CantileverCase base;
};

/// The rows of the table `vascsim validate cantilever` prints: the sound default at nu = 0.3 and 0.45 and
/// the variants it is compared with (no support growth, no stabiliser, h = 1.5 Delta, a stronger stabiliser,
/// Mueller-kernel volumes, the literal strain).
std::vector<CantileverConfiguration> cantilever_table_configurations();

}  // namespace vascsim
