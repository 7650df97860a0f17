#include "vascsim/experiments/force_displacement.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cstdlib>
#include <fstream>

#include "vascsim/core/error.hpp"
#include "vascsim/experiments/plot_script.hpp"
#include "vascsim/run/output_writer.hpp"
#include "vascsim/run/runner.hpp"

namespace vascsim {

std::vector<std::string> force_displacement_columns() {
  return {"step",         "displacement_m", "force_n",      "force_x_n", "force_y_n", "force_z_n",
          "torque_x_n_m", "torque_y_n_m",   "torque_z_n_m", "contacts",  "converged"};
}

ForceDisplacementResult run_force_displacement(const Scene& scene, const ForceDisplacementOptions& options) {
  namespace fs = std::filesystem;
  const std::size_t tool = find_tool(scene, options.tool, "force-displacement");
  const RigidObstacle& ob = scene.obstacles[tool];
  if (!(ob.motion_m.norm() > 0.0))
    throw InputError(fmt::format("{}: tool '{}' does not move: give it push_m (catheter) or motion_m",
                                 scene.file, ob.name));
  std::vector<StepRecord> records;
  RunOptions run;
  run.out_dir = options.out_dir;
  run.on_step = [&](const StepRecord& r, int total) {
    records.push_back(r);
    if (options.on_step) options.on_step(r, total);
  };
  ForceDisplacementResult result;
  result.summary = run_scene(scene, run);

  const OutputWriter out(options.out_dir);
  CsvTable csv =
      out.table("force_displacement.csv", force_displacement_columns(),
                fmt::format("{}: tool '{}', model {}; force_n: the tool's force on the tissue along its "
                            "push, N (as in summary.json); force_x_n .. torque_z_n_m: the force and torque "
                            "the tissue exerts on the tool (N, N m about the tool point)",
                            scene.name, ob.name, scene.model));
  result.csv = csv.file();
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : records) {
    const ObstacleMeasure& m = r.obstacles.at(tool);
    // The vector columns are on the tool (force_n, the scalar, is the same either way); + 0.0 turns -0 into
    // 0.
    const Vec3 f = -m.force_vector_n + Vec3::Zero(), t = -m.torque_vector_n_m + Vec3::Zero();
    csv.add_row(fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{},{}", r.step,
                            m.displacement_m, m.force_n, f.x(), f.y(), f.z(), t.x(), t.y(), t.z(), m.contacts,
                            r.report.converged ? 1 : 0));
    rows.push_back({{"displacement_m", m.displacement_m}, {"force_n", m.force_n}});
  }
  result.summary["force_displacement"] = {
      {"tool", ob.name}, {"csv", result.csv.filename().string()}, {"rows", rows}};

  if (options.plot) {
    const fs::path script =
        options.plot_script.empty() ? bundled_script("plot_force_displacement.py") : options.plot_script;
    const fs::path png = options.out_dir / "force_displacement.png";
    const PlotOutcome plot = run_plot_script(
        script, {result.csv.string(), "--out", png.string(), "--label", scene.model, "--title", scene.name},
        png, options.python);
    result.png = plot.png;
    result.plot_problem = plot.problem;
    if (!result.plot_problem.empty())
      result.summary["force_displacement"]["plot_problem"] = result.plot_problem;
    else
      result.summary["force_displacement"]["png"] = png.filename().string();
  }
  out.write_summary(result.summary);
  return result;
}

}  // namespace vascsim
