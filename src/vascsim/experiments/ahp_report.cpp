#include "vascsim/experiments/ahp_report.hpp"

#include "vascsim/experiments/plot_script.hpp"
#include "vascsim/run/output_writer.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <cstdlib>
#include <fstream>

#include "vascsim/core/error.hpp"

namespace vascsim::ahp {

namespace {

// A CSV field: quoted if it holds a comma, a quote or a newline.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string opt(const std::optional<double>& v, const char* format) {
  return v ? fmt::format(fmt::runtime(format), *v) : std::string();
}

std::string md_opt(const std::optional<double>& v, const char* format) {
  return v ? fmt::format(fmt::runtime(format), *v) : std::string("–");
}

nlohmann::json json_opt(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

struct MatrixRow {
  std::string name, scale;
  const PairwiseAnalysis* a;
  long n;
};

std::vector<MatrixRow> matrices(const Hierarchy& h) {
  std::vector<MatrixRow> rows;
  rows.push_back({"criteria", to_string(h.scale), &h.analysis, static_cast<long>(h.matrix.rows())});
  for (const auto& c : h.criteria)
    rows.push_back(
        {c.id + " indicators", to_string(c.scale), &c.analysis, static_cast<long>(c.matrix.rows())});
  return rows;
}

const Criterion& criterion_of(const Hierarchy& h, const Indicator& in) {
  for (const auto& c : h.criteria)
    if (c.id == in.criterion) return c;
  throw std::logic_error("indicator without its criterion");
}

char source_letter(ScoreSource s) {
  switch (s) {
    case ScoreSource::measured:
      return 'm';
    case ScoreSource::rated:
      return 'r';
    case ScoreSource::paper:
      return 'p';
    case ScoreSource::missing:
      return '-';
  }
  return '?';
}

}  // namespace

std::string weights_csv(const AhpReport& r) {
  const Hierarchy& h = r.hierarchy;
  std::string s =
      "indicator,name,criterion,criterion_weight,local_weight,global_weight,paper_criterion_weight,"
      "paper_local_weight,paper_global_weight,weight_used\n";
  for (std::size_t i = 0; i < h.indicators.size(); ++i) {
    const Indicator& in = h.indicators[i];
    const Criterion& c = criterion_of(h, in);
    s += fmt::format("{},{},{},{:.6f},{:.6f},{:.6f},{},{},{},{:.6f}\n", in.id, csv_field(in.name), c.id,
                     c.weight, in.local_weight, in.global_weight, opt(c.paper_weight, "{:.3f}"),
                     opt(in.paper_local_weight, "{:.3f}"), opt(in.paper_global_weight, "{:.3f}"),
                     r.weights[static_cast<Eigen::Index>(i)]);
  }
  return s;
}

std::string consistency_csv(const AhpReport& r) {
  std::string s = "matrix,scale,n,lambda_max,ci,ri,cr\n";
  for (const auto& m : matrices(r.hierarchy))
    s += fmt::format("{},{},{},{:.6f},{:.6f},{:.2f},{:.6f}\n", csv_field(m.name), m.scale, m.n,
                     m.a->lambda_max, m.a->ci, m.a->random_index, m.a->cr);
  return s;
}

std::string scores_csv(const AhpReport& r) {
  std::string s = "model,name,reference,comprehensive_score,paper_comprehensive_score,weight_covered,missing";
  for (const auto& in : r.hierarchy.indicators) s += fmt::format(",{0},{0}_source", in.id);
  s += "\n";
  for (const auto& m : r.models) {
    s += fmt::format("{},{},{},{},{},{:.6f},{}", m.id, csv_field(m.name), csv_field(m.reference),
                     opt(m.comprehensive_score, "{:.3f}"), opt(m.paper_comprehensive_score, "{:.3f}"),
                     m.weight_covered, fmt::join(m.missing, " "));
    for (const auto& sc : m.scores) s += fmt::format(",{},{}", opt(sc.score, "{:.3f}"), to_string(sc.source));
    s += "\n";
  }
  return s;
}

std::string indicator_scores_csv(const AhpReport& r) {
  std::string s = "model,indicator,score,source,value,unit,measure,level,weight,unused_rating\n";
  for (const auto& m : r.models)
    for (std::size_t i = 0; i < m.scores.size(); ++i) {
      const auto& sc = m.scores[i];
      s += fmt::format("{},{},{},{},{},{},{},{},{:.6f},{}\n", m.id, sc.indicator, opt(sc.score, "{:.3f}"),
                       to_string(sc.source), opt(sc.value, "{:.6g}"), sc.unit, sc.measure, csv_field(sc.band),
                       r.weights[static_cast<Eigen::Index>(i)], opt(sc.unused_rating, "{:.3f}"));
    }
  return s;
}

std::string markdown(const AhpReport& r) {
  const Hierarchy& h = r.hierarchy;
  std::string s = "# AHP force-tactile perception evaluation (Zhang et al. 2021, Tables 1-3, Eq. 40)\n\n";
  s += fmt::format("- hierarchy: {}\n- bands (Table 2): {}\n- ratings: {} (source: {})\n", h.file,
                   r.standard.file, r.ratings_file, r.ratings_source == "paper" ? "the paper" : "a study");
  s += fmt::format("- measurements: {}\n", r.measurements_file.empty() ? "none" : r.measurements_file);
  s += fmt::format("- weights in Eq. 40: {}\n\n",
                   r.paper_weights ? "Table 1's printed W_i" : "computed from the pairwise matrices");

  s += "## Weights (Table 1)\n\n";
  s += "| criterion | W_C | W_C paper | indicator | W_I | W_I paper | W_i | W_i paper |\n";
  s += "|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : h.criteria)
    for (std::size_t k = 0; k < c.indicators.size(); ++k) {
      const Indicator& in = h.indicators[c.indicators[k]];
      s += fmt::format("| {} | {} | {} | {} {} | {:.4f} | {} | {:.4f} | {} |\n",
                       k == 0 ? c.id + " " + c.name : "", k == 0 ? fmt::format("{:.4f}", c.weight) : "",
                       k == 0 ? md_opt(c.paper_weight, "{:.3f}") : "", in.id, in.name, in.local_weight,
                       md_opt(in.paper_local_weight, "{:.3f}"), in.global_weight,
                       md_opt(in.paper_global_weight, "{:.3f}"));
    }

  s += "\n## Consistency\n\n| matrix | scale | n | lambda_max | CI | RI | CR "
       "|\n|---|---|---|---|---|---|---|\n";
  for (const auto& m : matrices(h))
    s += fmt::format("| {} | {} | {} | {:.4f} | {:.4f} | {:.2f} | {:.4f} |\n", m.name, m.scale, m.n,
                     m.a->lambda_max, m.a->ci, m.a->random_index, m.a->cr);

  s += "\n## Scores (Eq. 40: G = sum W_i beta_i)\n\n";
  s += "Per indicator: the score on 0-100 and its source (m measured, r rated by a study, p the paper's). "
       "G is given only when every indicator has a score.\n\n| model |";
  for (const auto& in : h.indicators) s += " " + in.id + " |";
  s += " G | G printed by the paper | weight covered |\n|---|";
  for (std::size_t i = 0; i < h.indicators.size(); ++i) s += "---|";
  s += "---|---|---|\n";
  for (const auto& m : r.models) {
    s += "| " + m.name + (m.reference.empty() ? "" : " " + m.reference) + " |";
    for (const auto& sc : m.scores)
      s += sc.score ? fmt::format(" {:.1f} {} |", *sc.score, source_letter(sc.source)) : std::string(" – |");
    s += fmt::format(" {} | {} | {:.3f} |\n", md_opt(m.comprehensive_score, "{:.3f}"),
                     md_opt(m.paper_comprehensive_score, "{:.3f}"), m.weight_covered);
  }

  bool any = false;
  std::string t =
      "\n## Measured figures (Table 2 bands)\n\n| model | indicator | value | level | score "
      "|\n|---|---|---|---|---|\n";
  for (const auto& m : r.models)
    for (const auto& sc : m.scores)
      if (sc.source == ScoreSource::measured) {
        any = true;
        t += fmt::format("| {} | {} | {:.4g} {} | {} | {:.3f} |\n", m.id, sc.indicator, *sc.value, sc.unit,
                         sc.band, *sc.score);
      }
  if (any) s += t;
  return s;
}

nlohmann::json to_json(const AhpReport& r) {
  const Hierarchy& h = r.hierarchy;
  nlohmann::json j;
  j["inputs"] = {{"hierarchy", h.file},
                 {"bands", r.standard.file},
                 {"ratings", r.ratings_file},
                 {"ratings_source", r.ratings_source},
                 {"measurements", r.measurements_file.empty() ? nlohmann::json(nullptr)
                                                              : nlohmann::json(r.measurements_file)},
                 {"weights_in_eq40", r.paper_weights ? "paper" : "computed"}};
  j["goal"] = h.goal;
  nlohmann::json cons = nlohmann::json::array();
  for (const auto& m : matrices(h))
    cons.push_back({{"matrix", m.name},
                    {"scale", m.scale},
                    {"n", m.n},
                    {"lambda_max", m.a->lambda_max},
                    {"ci", m.a->ci},
                    {"ri", m.a->random_index},
                    {"cr", m.a->cr}});
  j["consistency"] = cons;
  nlohmann::json crit = nlohmann::json::array();
  for (const auto& c : h.criteria) {
    nlohmann::json ind = nlohmann::json::array();
    for (auto k : c.indicators) {
      const Indicator& in = h.indicators[k];
      ind.push_back({{"id", in.id},
                     {"name", in.name},
                     {"local_weight", in.local_weight},
                     {"global_weight", in.global_weight},
                     {"paper_local_weight", json_opt(in.paper_local_weight)},
                     {"paper_global_weight", json_opt(in.paper_global_weight)},
                     {"weight_used", r.weights[static_cast<Eigen::Index>(k)]}});
    }
    crit.push_back({{"id", c.id},
                    {"name", c.name},
                    {"weight", c.weight},
                    {"paper_weight", json_opt(c.paper_weight)},
                    {"indicators", ind}});
  }
  j["criteria"] = crit;
  nlohmann::json models = nlohmann::json::array();
  for (const auto& m : r.models) {
    nlohmann::json scores = nlohmann::json::array();
    for (const auto& sc : m.scores) {
      nlohmann::json e = {{"indicator", sc.indicator},
                          {"score", json_opt(sc.score)},
                          {"source", to_string(sc.source)},
                          {"level", sc.band.empty() ? nlohmann::json(nullptr) : nlohmann::json(sc.band)}};
      if (sc.value) e["measured"] = {{"measure", sc.measure}, {"value", *sc.value}, {"unit", sc.unit}};
      if (sc.unused_rating) e["unused_rating"] = *sc.unused_rating;
      scores.push_back(e);
    }
    models.push_back({{"id", m.id},
                      {"name", m.name},
                      {"reference", m.reference},
                      {"comprehensive_score", json_opt(m.comprehensive_score)},
                      {"paper_comprehensive_score", json_opt(m.paper_comprehensive_score)},
                      {"weight_covered", m.weight_covered},
                      {"missing", m.missing},
                      {"scores", scores}});
  }
  j["models"] = models;
  return j;
}

Outputs write_outputs(const AhpReport& r, const OutputOptions& o) {
  const OutputWriter folder(o.out_dir);
  Outputs out;
  auto write = [&](const std::string& name, const std::string& text) {
    folder.write_text(name, text);
    out.files.push_back(folder.path(name));
  };
  write("ahp_weights.csv", weights_csv(r));
  write("ahp_consistency.csv", consistency_csv(r));
  write("ahp_scores.csv", scores_csv(r));
  write("ahp_indicator_scores.csv", indicator_scores_csv(r));
  write("ahp_report.md", markdown(r));
  write("ahp_report.json", to_json(r).dump(2) + "\n");
  if (o.plot) {
    const std::filesystem::path script =
        o.plot_script.empty() ? bundled_script("plot_ahp.py") : o.plot_script;
    const std::filesystem::path png = folder.path("ahp_scores.png");
    const PlotOutcome plot = run_plot_script(
        script, {folder.path("ahp_scores.csv").string(), "--out", png.string()}, png, o.python);
    out.png = plot.png;
    out.plot_problem = plot.problem;
  }
  return out;
}

}  // namespace vascsim::ahp
