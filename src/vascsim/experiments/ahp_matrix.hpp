#pragma once
// Pairwise comparison matrices of the analytic hierarchy process (AHP; Saaty, "The Analytic Hierarchy
// Process", McGraw-Hill 1980), as used by the paper's force-tactile perception evaluation (Table 1):
// validation of a matrix, its priority vector (the principal right eigenvector, normalised to sum 1),
// lambda_max, the consistency index CI = (lambda_max - n)/(n - 1) and the consistency ratio CR = CI/RI(n)
// against Saaty's random index. A matrix with CR > 0.1 is rejected. docs/ahp.md states the rules.

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace vascsim::ahp {

/// What the entries of a matrix may be.
enum class JudgementScale {
  /// Saaty's fundamental scale: 1, 2, ..., 9 and their reciprocals (one judgement per pair).
  saaty,
  /// Any value in [1/9, 9], e.g. the element-wise geometric mean of several raters' Saaty judgements.
  aggregate,
  /// Any positive ratio, e.g. a_ij = w_i / w_j derived from known weights (not a judgement).
  ratio,
};
JudgementScale parse_scale(const std::string& name);  ///< "saaty", "aggregate", "ratio"
std::string to_string(JudgementScale scale);

/// |a_ij * a_ji - 1| allowed for a reciprocal pair, and the relative distance allowed between an entry and
/// the scale value it stands for (0.333 for 1/3 and 0.143 for 1/7 pass; 0.33 does not).
inline constexpr double kReciprocalTolerance = 5e-3;
inline constexpr double kScaleTolerance = 5e-3;
/// Saaty's acceptance limit for the consistency ratio.
inline constexpr double kMaxConsistencyRatio = 0.1;
/// Largest matrix with a tabulated random index.
inline constexpr int kMaxMatrixSize = 10;

/// Saaty's random index RI(n) for n = 1..10: 0, 0, 0.58, 0.90, 1.12, 1.24, 1.32, 1.41, 1.45, 1.49
/// (Saaty 1980, the mean CI of random reciprocal matrices on the 1-9 scale). Throws std::out_of_range
/// outside 1..10.
double random_index(int n);

struct PairwiseAnalysis {
  Eigen::VectorXd weights;  ///< principal right eigenvector, all entries > 0, sum 1
  double lambda_max = 0.0;  ///< principal eigenvalue (>= n for a reciprocal matrix)
  double ci = 0.0;          ///< (lambda_max - n)/(n - 1); 0 for n <= 2
  double random_index = 0.0;
  double cr = 0.0;  ///< CI/RI(n); 0 for n <= 2 (every reciprocal 1x1 or 2x2 matrix is consistent)
};

/// Where a matrix came from, for messages: "<file>: key '<key>' (<name>)" plus the element labels.
struct MatrixSource {
  std::string file;
  std::string key;
  std::string name;                       ///< what the matrix compares, e.g. "C2 indicators" (optional)
  std::vector<std::string> labels;        ///< the compared elements, in row order (optional)
  std::string where() const;              ///< "<file>: key '<key>' (<name>)"
  std::string entry(int i, int j) const;  ///< "entry (I1, I3)" (labels) or "entry [1][3]" (1-based)
};

/// Checks a matrix: square, 1..kMaxMatrixSize rows (as many as labels, if labels are given), finite
/// and positive, unit diagonal, reciprocal within kReciprocalTolerance, entries on `scale` (within
/// kScaleTolerance). Returns the matrix the computation uses: the upper triangle (snapped to the exact
/// scale value for `saaty`) with its exact reciprocals below. Throws InputError naming file, key and entry.
Eigen::MatrixXd validate_pairwise(const Eigen::MatrixXd& a, JudgementScale scale, const MatrixSource& source);

/// Priority vector, lambda_max, CI and CR of a positive matrix (no validation, no rejection). Throws
/// NumericalError if the principal eigenpair is not real and positive (impossible for a positive matrix).
PairwiseAnalysis analyse_pairwise(const Eigen::MatrixXd& a);

/// validate_pairwise + analyse_pairwise + rejection: throws InputError naming the matrix if
/// CR > max_cr (+1e-12 for round-off). Saaty's rule: CR <= 0.1 is acceptable.
PairwiseAnalysis check_pairwise(const Eigen::MatrixXd& a, JudgementScale scale, const MatrixSource& source,
                                double max_cr = kMaxConsistencyRatio);

/// Reads a matrix from JSON: an array of rows, each an array of entries; an entry is a number or a
/// string "p" or "p/q" with p, q positive decimal numbers ("1/3", "0.567/0.056"). Throws InputError
/// naming the key and the entry. Size checks are validate_pairwise's.
Eigen::MatrixXd parse_matrix(const nlohmann::json& value, const MatrixSource& source);

}  // namespace vascsim::ahp
