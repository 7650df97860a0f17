#include "vascsim/experiments/ahp_evaluation.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>

#include "vascsim/core/bundled_files.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/json_reader.hpp"

namespace vascsim::ahp {

namespace {

nlohmann::json read_json(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path);
  if (!in)
    throw InputError(fmt::format("{}: cannot open the {} (missing or unreadable)", path.string(), what));
  try {
    return nlohmann::json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(fmt::format("{}: not valid JSON at byte {}: {}", path.string(), e.byte, e.what()));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
}

// Identifiers of criteria, indicators and models: letters, digits, '_' and '-'.
std::string checked_id(JsonReader& r, const std::string& key) {
  const std::string id = r.required_string(key);
  const bool ok = !id.empty() && std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (!ok) r.fail(key, fmt::format("'{}' is not an identifier; use letters, digits, '_' and '-'", id));
  return id;
}

std::vector<double> number_array(JsonReader& r, const std::string& key, std::size_t size,
                                 const std::string& what) {
  const auto* v = r.raw(key);
  if (!v) r.fail(key, fmt::format("missing; {} is required", what));
  if (!v->is_array() || v->size() != size) r.fail(key, fmt::format("expected {}", what));
  std::vector<double> out;
  for (const auto& e : *v) {
    if (!e.is_number() || !std::isfinite(e.get<double>())) r.fail(key, fmt::format("expected {}", what));
    out.push_back(e.get<double>());
  }
  return out;
}

std::vector<std::string> string_array(JsonReader& r, const std::string& key, std::size_t size,
                                      const std::string& what) {
  const auto* v = r.raw(key);
  if (!v) r.fail(key, fmt::format("missing; {} is required", what));
  if (!v->is_array() || v->size() != size) r.fail(key, fmt::format("expected {}", what));
  std::vector<std::string> out;
  for (const auto& e : *v) {
    if (!e.is_string() || e.get<std::string>().empty()) r.fail(key, fmt::format("expected {}", what));
    out.push_back(e.get<std::string>());
  }
  return out;
}

std::optional<double> optional_number(JsonReader& r, const std::string& key, double lo, double hi) {
  if (!r.has(key)) return std::nullopt;
  return r.number(key, 0.0, lo, hi);
}

// The pairwise matrix of `n` elements under `key`; a single element needs none (it is [[1]]).
PairwiseAnalysis read_matrix(JsonReader& r, const std::string& key, const std::vector<std::string>& labels,
                             const std::string& name, JudgementScale scale, Eigen::MatrixXd& used) {
  MatrixSource src{r.file(), r.key_path(key), name, labels};
  const auto* v = r.raw(key);
  if (!v) {
    if (labels.size() > 1)
      r.fail(key, fmt::format("missing; the {}x{} pairwise comparison matrix of {} is required",
                              labels.size(), labels.size(), fmt::join(labels, ", ")));
    used = Eigen::MatrixXd::Ones(1, 1);
    return analyse_pairwise(used);
  }
  used = validate_pairwise(parse_matrix(*v, src), scale, src);
  return check_pairwise(used, JudgementScale::ratio, src);  // `used` is already on its scale
}

JudgementScale read_scale(JsonReader& r) {
  return parse_scale(r.string("scale", "saaty", {"saaty", "aggregate", "ratio"}));
}

}  // namespace

const Indicator* Hierarchy::find(const std::string& id) const {
  for (const auto& i : indicators)
    if (i.id == id) return &i;
  return nullptr;
}

// ------------------------------------------------------------------------------------------ hierarchy
Hierarchy parse_hierarchy(const nlohmann::json& doc, const std::string& file) {
  Hierarchy h;
  h.file = file;
  JsonReader root(doc, "", file);
  h.description = root.string("description", "");
  h.goal = root.required_string("goal");
  h.scale = read_scale(root);
  auto crit = root.array_of_objects("criteria", true);
  if (crit.empty()) root.fail("criteria", "empty; at least one criterion is required");
  std::set<std::string> ids;
  std::vector<std::string> crit_ids;
  for (auto& c : crit) {
    Criterion cr;
    cr.id = checked_id(c, "id");
    if (!ids.insert(cr.id).second) c.fail("id", fmt::format("'{}' is used twice; ids must be unique", cr.id));
    cr.name = c.required_string("name");
    cr.paper_weight = optional_number(c, "paper_weight", 0.0, 1.0);
    cr.scale = read_scale(c);
    auto ind = c.array_of_objects("indicators", true);
    if (ind.empty()) c.fail("indicators", "empty; at least one indicator is required");
    std::vector<std::string> labels;
    for (auto& i : ind) {
      Indicator in;
      in.id = checked_id(i, "id");
      if (!ids.insert(in.id).second)
        i.fail("id", fmt::format("'{}' is used twice; ids must be unique", in.id));
      in.name = i.required_string("name");
      in.criterion = cr.id;
      in.key = i.path();
      in.paper_local_weight = optional_number(i, "paper_weight", 0.0, 1.0);
      in.paper_global_weight = optional_number(i, "paper_global_weight", 0.0, 1.0);
      i.finish();
      labels.push_back(in.id);
      cr.indicators.push_back(h.indicators.size());
      h.indicators.push_back(in);
    }
    cr.analysis = read_matrix(c, "matrix", labels, cr.id + " indicators", cr.scale, cr.matrix);
    c.finish();
    crit_ids.push_back(cr.id);
    h.criteria.push_back(std::move(cr));
  }
  h.analysis = read_matrix(root, "matrix", crit_ids, "criteria", h.scale, h.matrix);
  root.finish();
  for (std::size_t c = 0; c < h.criteria.size(); ++c) {
    Criterion& cr = h.criteria[c];
    cr.weight = h.analysis.weights[static_cast<Eigen::Index>(c)];
    for (std::size_t k = 0; k < cr.indicators.size(); ++k) {
      Indicator& in = h.indicators[cr.indicators[k]];
      in.local_weight = cr.analysis.weights[static_cast<Eigen::Index>(k)];
      in.global_weight = cr.weight * in.local_weight;
    }
  }
  return h;
}

Hierarchy load_hierarchy(const std::filesystem::path& path) {
  return parse_hierarchy(read_json(path, "AHP hierarchy file"), path.string());
}

// -------------------------------------------------------------------------- evaluation standard (Table 2)
const std::vector<MeasureSpec>& measure_specs() {
  static const std::vector<MeasureSpec> specs = {
      {"visual_refresh_rate_hz", "Hz", "frames rendered per second during the interaction (paper Fig. 12)",
       1e-9, 1e5},
      {"haptic_rate_hz", "Hz", "achieved rate of the haptic (force feedback) loop", 1e-9, 1e6},
      {"update_time_ms", "ms", "wall time of one deformation update (paper Fig. 11)", 1e-9, 1e6},
      {"force_rms_error_percent", "%",
       "RMS of (F - F_ref) over the force-displacement samples, divided by the RMS of F_ref, times 100", 0.0,
       1e4},
  };
  return specs;
}

const MeasureSpec* find_measure(const std::string& key) {
  for (const auto& m : measure_specs())
    if (m.key == key) return &m;
  return nullptr;
}

Standard parse_standard(const nlohmann::json& doc, const std::string& file) {
  Standard s;
  s.file = file;
  JsonReader root(doc, "", file);
  s.description = root.string("description", "");
  {
    JsonReader b = root.object("score_bands");
    if (!root.has("score_bands"))
      root.fail("score_bands", "missing; {edges, labels, step_scores} is required");
    const auto* e = b.raw("edges");
    if (!e || !e->is_array() || e->size() < 3)
      b.fail("edges", "expected an array of at least 3 increasing scores from 0 to 100");
    const std::size_t nb = e->size() - 1;
    s.score_edges = number_array(b, "edges", nb + 1, "an array of increasing scores from 0 to 100");
    if (s.score_edges.front() != 0.0 || s.score_edges.back() != 100.0 ||
        !std::is_sorted(s.score_edges.begin(), s.score_edges.end(), std::less_equal<>()))
      b.fail("edges", "the score edges must increase strictly from 0 to 100");
    s.score_labels =
        string_array(b, "labels", nb, fmt::format("an array of {} band labels (one per band)", nb));
    s.step_scores =
        number_array(b, "step_scores", nb, fmt::format("an array of {} scores, one inside each band", nb));
    for (std::size_t k = 0; k < nb; ++k)
      if (s.step_scores[k] < s.score_edges[k] || s.step_scores[k] > s.score_edges[k + 1])
        b.fail("step_scores", fmt::format("{} is outside its band [{}, {}]", s.step_scores[k],
                                          s.score_edges[k], s.score_edges[k + 1]));
    b.finish();
  }
  const std::size_t nb = s.score_labels.size();
  const auto* ind = root.raw("indicators");
  if (!ind || !ind->is_object() || ind->empty())
    root.fail("indicators", "expected an object with one entry per indicator id (\"I1\": {...})");
  std::vector<std::string> measures;
  for (const auto& m : measure_specs()) measures.push_back(m.key);
  for (const auto& [id, value] : ind->items()) {
    JsonReader r(value, root.key_path("indicators") + "." + id, file);
    IndicatorStandard is;
    is.id = id;
    is.levels = string_array(r, "levels", nb, fmt::format("an array of {} level labels, worst first", nb));
    is.measure = r.string("measure", "", measures);
    is.edges_source = r.string("edges_source", "");
    r.string("note", "");
    if (is.measured()) {
      is.edges =
          number_array(r, "edges", nb + 1,
                       fmt::format("an array of {} band edges in {}, from the worst end to the best end",
                                   nb + 1, find_measure(is.measure)->unit));
      const bool up = is.edges.back() > is.edges.front();
      for (std::size_t k = 0; k + 1 < is.edges.size(); ++k)
        if (!(up ? is.edges[k + 1] > is.edges[k] : is.edges[k + 1] < is.edges[k]))
          r.fail("edges",
                 "the edges must be strictly monotone (increasing when higher is better, decreasing when "
                 "lower is better)");
      is.rule = r.string("rule", "linear", {"linear", "step"}) == "step" ? BandRule::step : BandRule::linear;
    } else {
      for (const char* k : {"edges", "rule"})
        if (r.has(k)) r.fail(k, "only for a measured indicator; give 'measure' too");
    }
    r.finish();
    s.indicators.emplace(id, std::move(is));
  }
  root.finish();
  return s;
}

Standard load_standard(const std::filesystem::path& path) {
  return parse_standard(read_json(path, "AHP bands file"), path.string());
}

BandScore score_measured(const Standard& s, const IndicatorStandard& ind, double value) {
  const auto& e = ind.edges;
  const int nb = static_cast<int>(e.size()) - 1;
  const bool up = e.back() > e.front();
  // Distance along the better direction from the worst edge.
  auto along = [&](double x) { return up ? x - e.front() : e.front() - x; };
  const double t = along(value);
  BandScore r;
  if (t <= 0.0) {
    r.band = 0;
  } else if (t >= along(e.back())) {
    r.band = nb - 1;
  } else {
    r.band = 0;
    while (r.band + 1 < nb && t >= along(e[static_cast<std::size_t>(r.band + 1)])) ++r.band;
  }
  const auto k = static_cast<std::size_t>(r.band);
  if (ind.rule == BandRule::step) {
    r.score = s.step_scores[k];
    return r;
  }
  if (t <= 0.0) {
    r.score = s.score_edges.front();
  } else if (t >= along(e.back())) {
    r.score = s.score_edges.back();
  } else {
    const double f = (t - along(e[k])) / (along(e[k + 1]) - along(e[k]));
    r.score = s.score_edges[k] + f * (s.score_edges[k + 1] - s.score_edges[k]);
  }
  return r;
}

// ---------------------------------------------------------------------------------- ratings, measurements
Ratings parse_ratings(const nlohmann::json& doc, const std::string& file, const Hierarchy& h,
                      const Standard& s) {
  Ratings out;
  out.file = file;
  JsonReader root(doc, "", file);
  out.source = root.required_string("source", {"paper", "study"});
  out.description = root.string("description", "");
  std::vector<std::string> ids;
  for (const auto& i : h.indicators) ids.push_back(i.id);
  std::set<std::string> seen;
  for (auto& m : root.array_of_objects("models", true)) {
    ModelRatings mr;
    mr.id = checked_id(m, "id");
    if (!seen.insert(mr.id).second) m.fail("id", fmt::format("model '{}' is listed twice", mr.id));
    mr.name = m.string("name", mr.id);
    mr.reference = m.string("reference", "");
    mr.notes = m.string("notes", "");
    mr.paper_comprehensive_score = optional_number(m, "paper_comprehensive_score", 0.0, 100.0);
    if (m.has("scores")) {
      JsonReader sc = m.object("scores");
      for (const auto& [key, value] : m.raw("scores")->items()) {
        if (!h.find(key))
          sc.fail(key,
                  fmt::format("unknown indicator; the hierarchy {} has {}", h.file, fmt::join(ids, ", ")));
        const auto it = s.indicators.find(key);
        if (value.is_string()) {
          const std::string label = value.get<std::string>();
          if (it == s.indicators.end())
            sc.fail(key, fmt::format("the bands file {} has no levels for it", s.file));
          const auto& lv = it->second.levels;
          const auto pos = std::find(lv.begin(), lv.end(), label);
          if (pos == lv.end())
            sc.fail(key, fmt::format("unknown level '{}'; allowed: a score in [0, 100] or one of: {}", label,
                                     fmt::join(lv, ", ")));
          mr.scores[key] = s.step_scores[static_cast<std::size_t>(pos - lv.begin())];
          sc.raw(key);
        } else {
          mr.scores[key] = sc.number(key, 0.0, 0.0, 100.0);
        }
      }
      sc.finish();
    }
    m.finish();
    out.models.push_back(std::move(mr));
  }
  root.finish();
  return out;
}

Ratings load_ratings(const std::filesystem::path& path, const Hierarchy& h, const Standard& s) {
  return parse_ratings(read_json(path, "AHP ratings file"), path.string(), h, s);
}

Measurements parse_measurements(const nlohmann::json& doc, const std::string& file) {
  Measurements out;
  out.file = file;
  JsonReader root(doc, "", file);
  out.source = root.string("source", "");
  out.description = root.string("description", "");
  std::set<std::string> seen;
  for (auto& m : root.array_of_objects("models", true)) {
    ModelMeasurements mm;
    mm.id = checked_id(m, "id");
    if (!seen.insert(mm.id).second) m.fail("id", fmt::format("model '{}' is listed twice", mm.id));
    mm.name = m.string("name", "");
    mm.notes = m.string("notes", "");
    if (m.has("nodes")) mm.nodes = m.integer("nodes", 0, 1, 100000000);
    for (const auto& spec : measure_specs())
      if (m.has(spec.key)) mm.values[spec.key] = m.number(spec.key, 0.0, spec.lo, spec.hi);
    m.finish();
    out.models.push_back(std::move(mm));
  }
  root.finish();
  return out;
}

Measurements load_measurements(const std::filesystem::path& path) {
  return parse_measurements(read_json(path, "AHP measurements file"), path.string());
}

// -------------------------------------------------------------------------------------------- scoring
double comprehensive_score(const Eigen::VectorXd& weights, const Eigen::VectorXd& scores) {
  if (weights.size() != scores.size())
    throw std::invalid_argument(
        fmt::format("comprehensive_score: {} weights but {} scores", weights.size(), scores.size()));
  return weights.dot(scores);
}

std::string to_string(ScoreSource source) {
  switch (source) {
    case ScoreSource::measured:
      return "measured";
    case ScoreSource::rated:
      return "rated";
    case ScoreSource::paper:
      return "paper";
    case ScoreSource::missing:
      return "missing";
  }
  return "?";
}

namespace {

// The bands must describe exactly the hierarchy's indicators.
void check_bands_match(const Hierarchy& h, const Standard& s) {
  std::vector<std::string> ids;
  for (const auto& i : h.indicators) ids.push_back(i.id);
  for (const auto& i : h.indicators)
    if (!s.indicators.count(i.id))
      throw InputError(fmt::format("{}: key 'indicators.{}': missing; the hierarchy {} has indicator {} ({})",
                                   s.file, i.id, h.file, i.id, i.name));
  for (const auto& [id, is] : s.indicators)
    if (!h.find(id))
      throw InputError(fmt::format("{}: key 'indicators.{}': not an indicator of the hierarchy {} ({})",
                                   s.file, id, h.file, fmt::join(ids, ", ")));
}

// W_i of every indicator: the hierarchy's (from its matrices) or Table 1's printed ones.
Eigen::VectorXd indicator_weights(const Hierarchy& h, bool paper_weights) {
  const auto n = static_cast<Eigen::Index>(h.indicators.size());
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Indicator& in = h.indicators[static_cast<std::size_t>(i)];
    if (paper_weights && !in.paper_global_weight)
      throw InputError(
          fmt::format("{}: key '{}.paper_global_weight': missing; the paper's weights (Table 1's W_i) "
                      "are needed for every indicator of {}",
                      h.file, in.key, in.id));
    w[i] = paper_weights ? *in.paper_global_weight : in.global_weight;
  }
  return w;
}

// One indicator's score for one model: measured (Table 2's band of the value) before rated.
IndicatorScore score_indicator(const Standard& s, const IndicatorStandard& is, const std::string& indicator,
                               const ModelRatings* mr, const ModelMeasurements* mm, ScoreSource rated) {
  IndicatorScore sc;
  sc.indicator = indicator;
  std::optional<double> rating;
  if (mr) {
    const auto it = mr->scores.find(indicator);
    if (it != mr->scores.end()) rating = it->second;
  }
  std::optional<double> value;
  if (is.measured() && mm) {
    const auto it = mm->values.find(is.measure);
    if (it != mm->values.end()) value = it->second;
  }
  if (value) {
    const BandScore b = score_measured(s, is, *value);
    sc.score = b.score;
    sc.source = ScoreSource::measured;
    sc.value = value;
    sc.measure = is.measure;
    sc.unit = find_measure(is.measure)->unit;
    sc.band = is.levels[static_cast<std::size_t>(b.band)];
    sc.unused_rating = rating;
  } else if (rating) {
    sc.score = rating;
    sc.source = rated;
    // The level whose score band holds the rating (a score on an inner edge: the better band).
    std::size_t k = 0;
    while (k + 1 < is.levels.size() && *rating >= s.score_edges[k + 1]) ++k;
    sc.band = is.levels[k];
  }
  return sc;
}

}  // namespace

AhpReport evaluate(const Hierarchy& h, const Standard& s, const Ratings& ratings, const Measurements* meas,
                   bool paper_weights) {
  check_bands_match(h, s);
  AhpReport rep;
  rep.hierarchy = h;
  rep.standard = s;
  rep.ratings_file = ratings.file;
  rep.ratings_source = ratings.source;
  rep.ratings_description = ratings.description;
  if (meas) {
    rep.measurements_file = meas->file;
    rep.measurements_source = meas->source;
  }
  rep.paper_weights = paper_weights;
  rep.weights = indicator_weights(h, paper_weights);
  const auto n = static_cast<Eigen::Index>(h.indicators.size());

  // Models: the ratings file's, then those only measured.
  std::vector<std::string> order;
  for (const auto& m : ratings.models) order.push_back(m.id);
  if (meas)
    for (const auto& m : meas->models)
      if (std::find(order.begin(), order.end(), m.id) == order.end()) order.push_back(m.id);

  const ScoreSource rated = ratings.source == "paper" ? ScoreSource::paper : ScoreSource::rated;
  for (const auto& id : order) {
    const ModelRatings* mr = nullptr;
    const ModelMeasurements* mm = nullptr;
    for (const auto& m : ratings.models)
      if (m.id == id) mr = &m;
    if (meas)
      for (const auto& m : meas->models)
        if (m.id == id) mm = &m;
    ModelResult res;
    res.id = id;
    res.name = mr ? mr->name : (mm && !mm->name.empty() ? mm->name : id);
    res.reference = mr ? mr->reference : "";
    if (mr) res.paper_comprehensive_score = mr->paper_comprehensive_score;
    Eigen::VectorXd beta = Eigen::VectorXd::Zero(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Indicator& in = h.indicators[static_cast<std::size_t>(i)];
      IndicatorScore sc = score_indicator(s, s.indicators.at(in.id), in.id, mr, mm, rated);
      if (sc.score) {
        beta[i] = *sc.score;
        res.weight_covered += rep.weights[i];
      } else {
        res.missing.push_back(in.id);
      }
      res.scores.push_back(std::move(sc));
    }
    if (res.missing.empty()) res.comprehensive_score = comprehensive_score(rep.weights, beta);
    rep.models.push_back(std::move(res));
  }
  return rep;
}

AhpReport run_ahp(const AhpInputs& in) {
  const Hierarchy h = load_hierarchy(in.hierarchy);
  const Standard s = load_standard(in.bands);
  const Ratings r = load_ratings(in.ratings, h, s);
  std::optional<Measurements> m;
  if (in.measurements) m = load_measurements(*in.measurements);
  return evaluate(h, s, r, m ? &*m : nullptr, in.paper_weights);
}

std::filesystem::path default_data_dir() {
  return bundled_file("data/ahp");
}

}  // namespace vascsim::ahp
