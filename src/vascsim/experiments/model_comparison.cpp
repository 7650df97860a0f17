#include "vascsim/experiments/model_comparison.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "vascsim/core/error.hpp"
#include "vascsim/experiments/force_displacement.hpp"
#include "vascsim/experiments/plot_script.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/output_writer.hpp"

namespace vascsim {

namespace {

namespace fs = std::filesystem;

// The curve of OUT/<model>/force_displacement.csv (comment lines start with '#'); false if there is none.
bool read_curve(const fs::path& csv, ModelCurve& c) {
  std::ifstream in(csv);
  if (!in) return false;
  std::string line;
  std::vector<std::string> header;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::stringstream ss(l);
    for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
    return out;
  };
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = split(line);
      continue;
    }
    const std::vector<std::string> f = split(line);
    auto at = [&](const std::string& name) {
      const auto it = std::find(header.begin(), header.end(), name);
      if (it == header.end() || static_cast<std::size_t>(it - header.begin()) >= f.size())
        throw InputError(fmt::format("{}: no column '{}'", csv.string(), name));
      return f[static_cast<std::size_t>(it - header.begin())];
    };
    c.displacement_m.push_back(std::stod(at("displacement_m")));
    c.force_n.push_back(std::stod(at("force_n")));
    c.converged.push_back(at("converged") == "1" ? 1 : 0);
  }
  return !c.displacement_m.empty();
}

// A finished single-model run: its summary.json has the force_displacement entry (written last).
bool read_finished(const fs::path& dir, ModelCurve& c) {
  std::ifstream in(dir / "summary.json");
  if (!in) return false;
  const nlohmann::json s = nlohmann::json::parse(in, nullptr, false);
  if (s.is_discarded() || !s.contains("force_displacement")) return false;
  if (s.contains("timings_s")) c.wall_s = s["timings_s"].value("total", 0.0);
  c.nodes = s.value("nodes", 0);
  return read_curve(dir / "force_displacement.csv", c);
}

ModelCurve run_one(const std::string& scene_path, const std::string& model, const ModelComparisonOptions& o) {
  ModelCurve c;
  c.model = model;
  const fs::path dir = o.out_dir / model;
  if (o.reuse && read_finished(dir, c)) {
    c.reused = true;
    if (o.progress) o.progress(fmt::format("{}: reusing {}", model, (dir / "summary.json").string()));
    return c;
  }
  c = ModelCurve{};
  c.model = model;
  std::vector<std::string> sets = o.overrides;
  sets.push_back("model=" + model);
  const Scene scene = load_scene(scene_path, sets);
  ForceDisplacementOptions fd;
  fd.out_dir = dir;
  fd.tool = o.tool;
  fd.plot = false;
  fd.python = o.python;
  if (o.on_step) fd.on_step = [&](const StepRecord& r, int total) { o.on_step(model, r, total); };
  run_force_displacement(scene, fd);
  if (!read_finished(dir, c))
    throw std::runtime_error("force-displacement: no curve written in " + dir.string());
  return c;
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  // x non-decreasing (load steps).
  for (std::size_t i = 1; i < x.size(); ++i)
    if (at <= x[i] && x[i] > x[i - 1])
      return y[i - 1] + (y[i] - y[i - 1]) * (at - x[i - 1]) / (x[i] - x[i - 1]);
  return y.back();
}

}  // namespace

ModelCurve converged_points(const ModelCurve& curve) {
  ModelCurve out = curve;
  out.displacement_m.clear();
  out.force_n.clear();
  out.converged.clear();
  for (std::size_t i = 0; i < curve.displacement_m.size(); ++i)
    if (curve.converged.empty() || curve.converged[i]) {
      out.displacement_m.push_back(curve.displacement_m[i]);
      out.force_n.push_back(curve.force_n[i]);
      out.converged.push_back(1);
    }
  return out;
}

void compare_to_reference(const ModelCurve& reference, ModelCurve& c) {
  const ModelCurve ref = converged_points(reference);
  const double d_max = *std::max_element(ref.displacement_m.begin(), ref.displacement_m.end());
  double f_ref_max = 0.0;
  for (double f : ref.force_n) f_ref_max = std::max(f_ref_max, std::abs(f));
  double sum2 = 0.0, ref2 = 0.0, deepest = -1.0;
  c.points = 0;
  for (std::size_t i = 0; i < c.displacement_m.size(); ++i) {
    const double d = c.displacement_m[i];
    if (!(d > 0.0) || d > d_max * (1.0 + 1e-9)) continue;
    if (i + 1 < c.displacement_m.size() && c.displacement_m[i + 1] == d)
      continue;  // a held point: keep the last
    const double f_ref = interpolate(ref.displacement_m, ref.force_n, d);
    sum2 += std::pow(c.force_n[i] - f_ref, 2);
    ref2 += f_ref * f_ref;
    ++c.points;
    if (d >= deepest) deepest = d, c.max_force_n = c.force_n[i], c.max_force_ratio = c.force_n[i] / f_ref;
  }
  c.rms_error_n = c.points > 0 ? std::sqrt(sum2 / c.points) : 0.0;
  c.rms_relative = f_ref_max > 0.0 ? c.rms_error_n / f_ref_max : 0.0;
  c.rms_percent = ref2 > 0.0 ? 100.0 * std::sqrt(sum2 / ref2) : 0.0;
}

ModelComparisonResult run_model_comparison(const std::string& scene_path, const ModelComparisonOptions& o) {
  if (o.models.empty()) throw InputError("force-displacement: --models needs at least one model");
  std::vector<std::string> models = {o.reference};
  for (const auto& m : o.models) {
    find_model(m);  // an unknown name fails before any run
    if (std::find(models.begin(), models.end(), m) == models.end()) models.push_back(m);
  }
  find_model(o.reference);
  ModelComparisonResult res;
  for (const auto& m : models) {
    if (o.progress) o.progress(fmt::format("model {} ({} of {})", m, res.curves.size() + 1, models.size()));
    res.curves.push_back(run_one(scene_path, m, o));
  }
  // The reference against itself on its converged points (0 by construction); every other model on all of its
  // points (a real-time model's frame that stopped at its iteration budget is what it shows).
  for (std::size_t k = 1; k < res.curves.size(); ++k) compare_to_reference(res.curves.front(), res.curves[k]);
  ModelCurve self = converged_points(res.curves.front());
  compare_to_reference(res.curves.front(), self);
  res.curves.front().rms_error_n = self.rms_error_n;
  res.curves.front().rms_relative = self.rms_relative;
  res.curves.front().rms_percent = self.rms_percent;
  res.curves.front().points = self.points;
  res.curves.front().max_force_n = self.max_force_n;
  res.curves.front().max_force_ratio = self.max_force_ratio;

  const OutputWriter out(o.out_dir);
  CsvTable csv = out.table(
      "force_displacement_models.csv", {"model", "displacement_m", "force_n", "converged"},
      fmt::format("{}: tool displacement (m) and the force the tissue exerts on it along the "
                  "reversed push (N), per model, and whether the step converged (1/0); reference {}",
                  scene_path, o.reference));
  for (const auto& c : res.curves)
    for (std::size_t i = 0; i < c.displacement_m.size(); ++i)
      csv.add_row(fmt::format("{},{:.9g},{:.9g},{}", c.model, c.displacement_m[i], c.force_n[i],
                              c.converged.empty() || c.converged[i] ? 1 : 0));
  res.csv = csv.file();
  CsvTable rms =
      out.table("rms_error.csv",
                {"model", "nodes", "points", "rms_error_n", "rms_relative", "rms_percent",
                 "max_depth_force_n", "max_depth_force_ratio", "wall_s"},
                fmt::format("{}: RMS of F - F_ref (N) at each model's displacements, relative to max "
                            "|F_ref| and in % of RMS(F_ref) there (docs/ahp.md I7); the force at the deepest "
                            "point (N) and its ratio to the reference; "
                            "wall time (s); reference {}",
                            scene_path, o.reference));
  nlohmann::json table = nlohmann::json::array();
  for (const auto& c : res.curves) {
    rms.add_row(fmt::format("{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g}", c.model, c.nodes, c.points,
                            c.rms_error_n, c.rms_relative, c.rms_percent, c.max_force_n, c.max_force_ratio,
                            c.wall_s));
    table.push_back({{"model", c.model},
                     {"nodes", c.nodes},
                     {"points", c.points},
                     {"rms_error_n", c.rms_error_n},
                     {"rms_relative", c.rms_relative},
                     {"rms_percent", c.rms_percent},
                     {"max_depth_force_n", c.max_force_n},
                     {"max_depth_force_ratio", c.max_force_ratio},
                     {"wall_s", c.wall_s},
                     {"reused", c.reused}});
  }
  res.rms_csv = rms.file();
  out.write_json("rms_error.json", {{"scene", scene_path}, {"reference", o.reference}, {"models", table}});
  res.rms_json = o.out_dir / "rms_error.json";
  if (o.plot) {
    std::vector<std::string> args;
    for (const auto& c : res.curves)
      args.push_back((o.out_dir / c.model / "force_displacement.csv").string());
    for (const auto& c : res.curves) args.insert(args.end(), {"--label", c.model});
    const fs::path png = o.out_dir / "force_displacement_models.png";
    args.insert(args.end(),
                {"--reference", "--out", png.string(), "--title", fs::path(scene_path).stem().string()});
    const PlotOutcome plot =
        run_plot_script(bundled_script("plot_force_displacement.py"), args, png, o.python);
    res.png = plot.png;
    res.plot_problem = plot.problem;
  }
  return res;
}

std::string model_comparison_table(const ModelComparisonResult& r) {
  std::string s =
      fmt::format("{:<18} {:>7} {:>6} {:>12} {:>9} {:>8} {:>14} {:>9} {:>9}\n", "model", "nodes", "points",
                  "rms_err_mN", "rms/Fmax", "rms_%", "F_deepest_mN", "F/F_ref", "wall_s");
  for (const auto& c : r.curves)
    s += fmt::format("{:<18} {:>7} {:>6} {:>12.4g} {:>9.3f} {:>8.1f} {:>14.4g} {:>9.3f} {:>9.1f}{}\n",
                     c.model, c.nodes, c.points, c.rms_error_n * 1e3, c.rms_relative, c.rms_percent,
                     c.max_force_n * 1e3, c.max_force_ratio, c.wall_s, c.reused ? " (reused)" : "");
  return s;
}

}  // namespace vascsim
