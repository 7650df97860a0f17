#include "vascsim/experiments/force_accuracy.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "vascsim/core/bundled_files.hpp"
#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

AccuracyCase read_case(const nlohmann::json& j) {
  AccuracyCase c;
  c.name = j.at("case").get<std::string>();
  c.scene = j.at("scene").get<std::string>();
  c.tool = j.at("loaded_by").get<std::string>() == "tool";
  c.basis = j.value("basis", std::string("linear"));
  c.outer_radius_m = j.at("outer_radius_m").get<double>();
  c.wall_thickness_m = j.at("wall_thickness_m").get<double>();
  for (const auto& r : j.at("rows"))
    c.rows.push_back({r.at("spacing_m").get<double>(), r.at("nodes").get<double>(),
                      r.at("force_n").get<double>(), r.at("error").get<double>()});
  std::sort(c.rows.begin(), c.rows.end(),
            [](const AccuracyRow& a, const AccuracyRow& b) { return a.nodes < b.nodes; });
  if (j.contains("finest_row_against")) {
    const auto& i = j.at("finest_row_against");
    c.independent = IndependentCheck{i.at("reference").get<std::string>(), i.at("error").get<double>(),
                                     i.at("where").get<std::string>()};
  }
  return c;
}

bool same(double a, double b) {
  return std::abs(a - b) <= 0.01 * std::max(std::abs(a), std::abs(b));
}

// The scene's local-fit basis as the table names it (the quadratic fit with the through-wall cube,
// quasi_static's default on walls, is a fit of its own with rows of its own).
std::string basis_name(const DiscretizationOptions& d) {
  const GradientBasis b = d.basis;
  if (b == GradientBasis::Quadratic) return d.wall_cube ? "quadratic_cube" : "quadratic";
  return b == GradientBasis::WallQuadratic ? "wall_quadratic" : "linear";
}

}  // namespace

ForceAccuracyTable ForceAccuracyTable::read(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("{}: cannot read the force accuracy table", file.string()));
  ForceAccuracyTable t;
  t.file = file;
  try {
    const nlohmann::json doc = nlohmann::json::parse(in);
    t.reference = doc.at("reference").get<std::string>();
    t.measured = doc.at("measured").get<std::string>();
    t.regenerate = doc.at("regenerate").get<std::string>();
    for (const auto& c : doc.at("cases")) {
      t.cases.push_back(read_case(c));
      if (t.cases.back().rows.empty())
        throw InputError(fmt::format("{}: case '{}' has no rows", file.string(), t.cases.back().name));
    }
    for (const auto& r : doc.at("substep_stiffness")) {
      t.substep_rules.push_back({r.at("model").get<std::string>(), r.at("substep_key").get<std::string>(),
                                 r.at("warn_above").get<double>(), r.at("measured").get<std::string>()});
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a force accuracy table ({})", file.string(), e.what()));
  }
  return t;
}

std::filesystem::path ForceAccuracyTable::default_file() {
  return bundled_file("data/calibration/force_accuracy.json");
}

AccuracyEstimate estimate_accuracy(const ForceAccuracyTable& table, const Scene& scene, double nodes) {
  AccuracyEstimate e;
  e.nodes = nodes;
  const std::string& type = scene.geometry.type;
  if (type != "tube" && type != "vessel") return e;
  e.graded = scene.geometry.refine.enabled;
  if (e.graded) return e;  // its node count says nothing of its resolution where the load acts
  const bool tool = !scene.obstacles.empty();
  const std::string basis = basis_name(scene.discretization);
  for (const AccuracyCase& c : table.cases)
    if (c.tool == tool && c.basis == basis && same(c.outer_radius_m, scene.geometry.tube.outer_radius_m) &&
        same(c.wall_thickness_m, scene.geometry.tube.wall_thickness_m))
      e.match = &c;
  if (e.match == nullptr) {
    double best = 1e300;
    for (const AccuracyCase& c : table.cases) {
      const double d = (c.tool == tool ? 0.0 : 10.0) + (c.basis == basis ? 0.0 : 5.0) +
                       std::abs(std::log(c.outer_radius_m / scene.geometry.tube.outer_radius_m)) +
                       std::abs(std::log(c.wall_thickness_m / scene.geometry.tube.wall_thickness_m));
      if (d < best) {
        best = d;
        e.nearest = &c;
      }
    }
    return e;
  }
  const std::vector<AccuracyRow>& rows = e.match->rows;
  if (nodes <= rows.front().nodes) {
    e.above = &rows.front();
    e.error = rows.front().error;
    return e;
  }
  if (nodes >= rows.back().nodes) {
    e.below = &rows.back();
    e.error = rows.back().error;
    return e;
  }
  std::size_t k = 1;
  while (rows[k].nodes < nodes) ++k;
  e.below = &rows[k - 1];
  e.above = &rows[k];
  const double t = std::log(nodes / e.below->nodes) / std::log(e.above->nodes / e.below->nodes);
  e.error = e.below->error + t * (e.above->error - e.below->error);
  return e;
}

std::string describe_accuracy(const ForceAccuracyTable& table, const AccuracyEstimate& e) {
  if (e.graded)
    return "not covered: the table's rows are uniform lattices, and a graded lattice's node count does not "
           "say how "
           "fine it is where the load acts (geometry.refine; docs/validation.md, 'Graded lattices')";
  if (e.match == nullptr) {
    if (e.nearest == nullptr)
      return fmt::format("not covered: the table's {} cases are vessels (tubes and swept vessels)",
                         table.cases.size());
    const AccuracyCase& c = *e.nearest;
    std::string line = fmt::format(
        "not covered: no case of the accuracy table has this vessel, loading and local-fit basis; the "
        "nearest is '{}' "
        "({}, outer radius {:.3g} mm, wall {:.3g} mm, {})",
        c.name, c.scene, 1e3 * c.outer_radius_m, 1e3 * c.wall_thickness_m,
        c.basis == "quadratic_cube" ? "the quadratic fit with the through-wall cube"
                                    : "the " + c.basis + " fit");
    if (c.independent)
      line += fmt::format(", whose finest row is {:+.1f} % against {}", 100.0 * c.independent->error,
                          c.independent->reference);
    return line;
  }
  auto row = [](const AccuracyRow& r) {
    return fmt::format("{:.3g} mm, {:.0f} nodes: {:+.1f} %", 1e3 * r.spacing_m, r.nodes, 100.0 * r.error);
  };
  std::string from;
  if (e.below && e.above)
    from = fmt::format("interpolated in log(nodes) between the rows [{}] and [{}]", row(*e.below),
                       row(*e.above));
  else if (e.above && std::abs(e.nodes / e.above->nodes - 1.0) < 0.005)
    from = fmt::format("the coarsest row [{}]", row(*e.above));
  else if (e.above)
    from = fmt::format("coarser than the coarsest row [{}]: expect at least this error", row(*e.above));
  else
    from = fmt::format("as fine as or finer than the finest row [{}], the reference", row(*e.below));
  std::string line = fmt::format("{:+.1f} % against the {} of case '{}' ({}; {})", 100.0 * e.error,
                                 table.reference, e.match->name, e.match->scene, from);
  // The two errors compound: force / reference = (1 + e) (1 + e_finest).
  if (const auto& i = e.match->independent)
    line += fmt::format(
        "; that finest row is itself {:+.1f} % against {} ({}), so about {:+.1f} % against that reference",
        100.0 * i->error, i->reference, i->where, 100.0 * ((1.0 + e.error) * (1.0 + i->error) - 1.0));
  return line;
}

double substep_stiffness_ratio(double substep_s, const Material& material, double spacing_m) {
  const double c_p = std::sqrt(material.p_wave_modulus() / material.density_kg_m3);
  const double r = substep_s * c_p / spacing_m;
  return r * r;
}

}  // namespace vascsim
