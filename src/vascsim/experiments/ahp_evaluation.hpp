#pragma once
// The paper's force-tactile perception evaluation (Zhang et al. 2021, section 3.3.3): an AHP hierarchy
// goal -> criteria C1-C3 -> indicators I1-I9 (Table 1), the evaluation standard that maps a measured
// figure or a rating to a score on 0-100 (Table 2), and the comprehensive score of Eq. 40,
// G = sum_i W_i * beta_Ii, for each compared model (Table 3). Inputs are four JSON files (data/ahp/,
// docs/ahp.md): the hierarchy with its pairwise matrices, the bands, the ratings a study fills in, and the
// measurements the timing and force-displacement experiments write.

#include <Eigen/Dense>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vascsim/experiments/ahp_matrix.hpp"

namespace vascsim::ahp {

// ------------------------------------------------------------------------------------------ hierarchy
struct Indicator {
  std::string id, name, criterion;  ///< "I7", "deformation accuracy", "C2"
  std::string key;                  ///< its key path in the file, "criteria.1.indicators.2"
  double local_weight = 0.0;        ///< W_Ii, within its criterion (principal eigenvector)
  double global_weight = 0.0;       ///< W_i = W_C * W_Ii
  std::optional<double> paper_local_weight, paper_global_weight;  ///< Table 1, if given in the file
};

struct Criterion {
  std::string id, name;
  double weight = 0.0;  ///< W_Ci
  std::optional<double> paper_weight;
  JudgementScale scale = JudgementScale::saaty;
  Eigen::MatrixXd matrix;               ///< as used (validated, exact reciprocals)
  PairwiseAnalysis analysis;            ///< of the indicator matrix
  std::vector<std::size_t> indicators;  ///< indices into Hierarchy::indicators
};

struct Hierarchy {
  std::string file, goal, description;
  JudgementScale scale = JudgementScale::saaty;  ///< of the criteria matrix
  Eigen::MatrixXd matrix;                        ///< criteria matrix, as used
  PairwiseAnalysis analysis;                     ///< of the criteria matrix
  std::vector<Criterion> criteria;
  std::vector<Indicator> indicators;  ///< all indicators, criterion by criterion, in file order
  const Indicator* find(const std::string& id) const;
};

/// Reads and checks a hierarchy (every matrix must pass check_pairwise). `file` names it in messages.
Hierarchy parse_hierarchy(const nlohmann::json& doc, const std::string& file);
Hierarchy load_hierarchy(const std::filesystem::path& path);

// -------------------------------------------------------------------------- evaluation standard (Table 2)
/// The measured figures an indicator can be scored from, with their units (fixed key names).
struct MeasureSpec {
  std::string key, unit, description;
  double lo, hi;  ///< allowed range (inclusive); rates and times must be > 0
};
const std::vector<MeasureSpec>& measure_specs();
const MeasureSpec* find_measure(const std::string& key);

enum class BandRule { linear, step };

struct IndicatorStandard {
  std::string id;
  std::vector<std::string> levels;  ///< one label per score band, worst first ("not fluent", ...)
  std::string measure;              ///< empty: rated only
  /// Measured indicators: band edges in the measure's unit, one more than the bands, strictly monotone
  /// from the worst end to the best end (decreasing when lower is better, e.g. update time).
  std::vector<double> edges;
  BandRule rule = BandRule::linear;
  std::string edges_source;  ///< where the edges come from (Table 2 or ours), free text
  bool measured() const { return !measure.empty(); }
};

struct Standard {
  std::string file, description;
  std::vector<double> score_edges;        ///< increasing, from 0 to 100: [0, 60, 70, 80, 90, 100]
  std::vector<std::string> score_labels;  ///< "<=60", "60~70", ...
  std::vector<double> step_scores;        ///< the score of a band for the step rule and for a level label
  std::map<std::string, IndicatorStandard> indicators;
};

Standard parse_standard(const nlohmann::json& doc, const std::string& file);
Standard load_standard(const std::filesystem::path& path);

struct BandScore {
  double score = 0.0;
  int band = 0;  ///< 0 = worst
};
/// The score of a measured value. Linear rule: linear between the band's edges and the band's score range,
/// clamped to the first/last score edge outside the outermost edges. Step rule: the band's step score.
/// A value exactly on an inner edge belongs to the better band.
BandScore score_measured(const Standard& standard, const IndicatorStandard& indicator, double value);

// ---------------------------------------------------------------------------------- ratings, measurements
struct ModelRatings {
  std::string id, name, reference, notes;
  std::map<std::string, double> scores;  ///< indicator id -> score on 0-100 (labels already mapped)
  std::optional<double> paper_comprehensive_score;
};
struct Ratings {
  std::string file, source, description;  ///< source: "paper" (transcribed) or "study" (ours)
  std::vector<ModelRatings> models;
};
/// Scores are numbers in [0, 100] or a level label of the indicator (-> that band's step score). Needs the
/// hierarchy (indicator ids) and the standard (labels).
Ratings parse_ratings(const nlohmann::json& doc, const std::string& file, const Hierarchy& hierarchy,
                      const Standard& standard);
Ratings load_ratings(const std::filesystem::path& path, const Hierarchy& hierarchy, const Standard& standard);

struct ModelMeasurements {
  std::string id, name, notes;
  std::optional<int> nodes;
  std::map<std::string, double> values;  ///< measure key -> value in its unit
};
struct Measurements {
  std::string file, source, description;
  std::vector<ModelMeasurements> models;
};
Measurements parse_measurements(const nlohmann::json& doc, const std::string& file);
Measurements load_measurements(const std::filesystem::path& path);

// -------------------------------------------------------------------------------------------- scoring
/// Eq. 40: G = sum_i W_i * beta_i. Throws std::invalid_argument if the sizes differ.
double comprehensive_score(const Eigen::VectorXd& weights, const Eigen::VectorXd& scores);

enum class ScoreSource { measured, rated, paper, missing };
std::string to_string(ScoreSource source);

struct IndicatorScore {
  std::string indicator;
  std::optional<double> score;
  ScoreSource source = ScoreSource::missing;
  std::optional<double> value;          ///< the measured figure (measured scores)
  std::string measure, unit;            ///< of the measured figure
  std::string band;                     ///< the Table 2 level of the score ("fluent", "65~85 Hz", ...)
  std::optional<double> unused_rating;  ///< a rating that a measurement took precedence over
};

struct ModelResult {
  std::string id, name, reference;
  std::vector<IndicatorScore> scores;               ///< one per indicator, in Hierarchy::indicators order
  std::optional<double> comprehensive_score;        ///< Eq. 40; none if any indicator has no score
  double weight_covered = 0.0;                      ///< sum of W_i over the indicators that have a score
  std::vector<std::string> missing;                 ///< indicators without a score
  std::optional<double> paper_comprehensive_score;  ///< Table 3, if the ratings file gives it
};

struct AhpInputs {
  std::filesystem::path hierarchy, bands, ratings;
  std::optional<std::filesystem::path> measurements;
  /// Use Table 1's printed W_i (the hierarchy's paper_global_weight) in Eq. 40 instead of the weights
  /// computed from the matrices.
  bool paper_weights = false;
};

struct AhpReport {
  Hierarchy hierarchy;
  Standard standard;
  std::string ratings_file, ratings_source, ratings_description;
  std::string measurements_file, measurements_source;  ///< empty without measurements
  bool paper_weights = false;
  Eigen::VectorXd weights;          ///< the W_i used in Eq. 40, Hierarchy::indicators order
  std::vector<ModelResult> models;  ///< ratings-file order, then models found only in the measurements
};

/// Scores every model: a measured figure (if the indicator has a measure and the model has that figure)
/// takes precedence over a rating; the rest come from the ratings; Eq. 40 when all are present.
AhpReport evaluate(const Hierarchy& hierarchy, const Standard& standard, const Ratings& ratings,
                   const Measurements* measurements, bool paper_weights);

/// Loads the files and evaluates. Throws InputError (one line naming file and key) for bad input.
AhpReport run_ahp(const AhpInputs& inputs);

/// data/ahp of the bundled files (core/bundled_files.hpp: the paper files).
std::filesystem::path default_data_dir();

}  // namespace vascsim::ahp
