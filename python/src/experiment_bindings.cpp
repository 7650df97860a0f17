// The experiments from Python, as the command line runs them (experiments/): a headless run of a scene
// (`vascsim run`), the force-displacement experiment (`vascsim experiment force-displacement`, the paper's
// Fig. 10), its comparison of several models (`--models`) and the MLS map checks (`vascsim validate mls`).
// Each writes the same files as the command; the GIL is released while it runs and Ctrl-C stops it between
// output points. What the library logs reaches Python at every output point (log_bridge.hpp): warnings as
// VascsimWarning, progress as INFO records; the lines of summary.json's "warnings" not logged as warnings
// come at the end (as `vascsim run` prints them). The package's wrappers (vascsim/__init__.py) call these, so
// warnings name their caller's line (stacklevel 2).

#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include <set>
#include <string>

#include "bindings.hpp"
#include "conversions.hpp"
#include "log_bridge.hpp"
#include "vascsim/experiments/force_displacement.hpp"
#include "vascsim/experiments/mls_validation.hpp"
#include "vascsim/experiments/model_comparison.hpp"
#include "vascsim/run/runner.hpp"

namespace vascsim::python {

namespace {

// The wrappers' callers: warnings.warn's stacklevel from inside a wrapper of vascsim/__init__.py.
constexpr int kCallerOfWrapper = 2;

// Called by the experiment after every output point, without the GIL: takes it, hands the log to Python
// (adding the warnings to `warned`), passes the record to the user's callback (if any) and stops the
// experiment (the Python exception propagates) on Ctrl-C or a warning the filter makes an error. Holds the
// callback by pointer (it outlives the experiment): the experiment may copy the function without the GIL.
std::function<void(const StepRecord&, int)> step_callback(const Scene& scene, const py::object& on_step,
                                                          std::set<std::string>& warned) {
  const py::object* callback = &on_step;
  return [&scene, callback, &warned](const StepRecord& r, int total) {
    py::gil_scoped_acquire gil;
    log_step(scene.name, scene.model, r, total);
    emit_log(kCallerOfWrapper, &warned);
    if (!callback->is_none()) (*callback)(record_to_dict(scene, r), total);
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  };
}

// After a run: what is left of the log, then summary.json's warnings not already issued from it (the run
// logs some as it finds them, others only into the summary).
void warn_the_rest(const nlohmann::json& summary, std::set<std::string>& warned) {
  emit_log(kCallerOfWrapper, &warned);
  for (const auto& w : summary.value("warnings", nlohmann::json::array()))
    if (warned.insert(w.get<std::string>()).second) warn(w.get<std::string>(), kCallerOfWrapper);
}

py::object run(const Scene& scene, const std::string& out_dir, const py::object& on_step) {
  std::set<std::string> warned;
  RunOptions o;
  o.out_dir = out_dir;
  o.on_step = step_callback(scene, on_step, warned);
  o.after_setup = [&scene](Simulation& sim) { log_accuracy_warnings(scene, sim); };  // as `vascsim run`
  nlohmann::json summary;
  {
    py::gil_scoped_release free;
    summary = run_scene(scene, o);
  }
  warn_the_rest(summary, warned);
  return to_python(summary);
}

py::dict force_displacement(const Scene& scene, const std::string& out_dir, const std::string& tool,
                            bool plot, const std::string& python, const py::object& on_step) {
  std::set<std::string> warned;
  ForceDisplacementOptions o;
  o.out_dir = out_dir;
  o.tool = tool;
  o.plot = plot;
  o.python = python;
  o.on_step = step_callback(scene, on_step, warned);
  ForceDisplacementResult r;
  {
    py::gil_scoped_release free;
    r = run_force_displacement(scene, o);
  }
  warn_the_rest(r.summary, warned);
  std::vector<double> u, f;
  for (const auto& row : r.summary["force_displacement"]["rows"]) {
    u.push_back(row["displacement_m"].get<double>());
    f.push_back(row["force_n"].get<double>());
  }
  py::dict d;
  d["displacement_m"] = py::array_t<double>(static_cast<py::ssize_t>(u.size()), u.data());
  d["force_n"] = py::array_t<double>(static_cast<py::ssize_t>(f.size()), f.data());
  d["csv"] = r.csv.string();
  d["png"] = r.png.empty() ? py::object(py::none()) : py::object(py::str(r.png.string()));
  d["plot_problem"] = r.plot_problem;
  d["summary"] = to_python(r.summary);
  return d;
}

py::dict curve_dict(const ModelCurve& c) {
  py::dict d;
  d["model"] = c.model;
  d["displacement_m"] =
      py::array_t<double>(static_cast<py::ssize_t>(c.displacement_m.size()), c.displacement_m.data());
  d["force_n"] = py::array_t<double>(static_cast<py::ssize_t>(c.force_n.size()), c.force_n.data());
  d["rms_error_n"] = c.rms_error_n;
  d["rms_relative"] = c.rms_relative;
  d["rms_percent"] = c.rms_percent;
  d["max_force_n"] = c.max_force_n;
  d["max_force_ratio"] = c.max_force_ratio;
  d["points"] = c.points;
  d["wall_s"] = c.wall_s;
  d["nodes"] = c.nodes;
  d["reused"] = c.reused;
  return d;
}

py::dict compare_models(const std::string& scene_path, const std::vector<std::string>& models,
                        const std::string& out_dir, const std::string& reference,
                        const std::vector<std::string>& overrides, const std::string& tool, bool reuse,
                        bool plot, const std::string& python) {
  ModelComparisonOptions o;
  o.out_dir = out_dir;
  o.models = models;
  o.reference = reference;
  o.overrides = overrides;
  o.tool = tool;
  o.reuse = reuse;
  o.plot = plot;
  o.python = python;
  o.progress = [](const std::string& line) {
    spdlog::info("{}", line);
  };  // reaches Python with the next step
  o.on_step = [](const std::string& model, const StepRecord& r, int total) {
    py::gil_scoped_acquire gil;
    log_step(model, model, r, total);
    emit_log(kCallerOfWrapper);
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  };
  ModelComparisonResult r;
  {
    py::gil_scoped_release free;
    r = run_model_comparison(scene_path, o);
  }
  emit_log(kCallerOfWrapper);
  py::list curves;
  for (const ModelCurve& c : r.curves) curves.append(curve_dict(c));
  py::dict d;
  d["curves"] = curves;
  d["csv"] = r.csv.string();
  d["rms_csv"] = r.rms_csv.string();
  d["rms_json"] = r.rms_json.string();
  d["png"] = r.png.empty() ? py::object(py::none()) : py::object(py::str(r.png.string()));
  d["plot_problem"] = r.plot_problem;
  d["table"] = model_comparison_table(r);
  return d;
}

}  // namespace

void bind_experiments(py::module_& m) {
  m.def("_run", &run, py::arg("scene"), py::arg("out_dir"), py::arg("on_step") = py::none());
  m.def("_force_displacement", &force_displacement, py::arg("scene"), py::arg("out_dir"),
        py::arg("tool") = "", py::arg("plot") = false, py::arg("python") = "/usr/bin/python3",
        py::arg("on_step") = py::none());
  m.def("_compare_models", &compare_models, py::arg("scene_path"), py::arg("models"), py::arg("out_dir"),
        py::arg("reference") = "quasi_static", py::arg("overrides") = std::vector<std::string>{},
        py::arg("tool") = "", py::arg("reuse") = false, py::arg("plot") = false,
        py::arg("python") = "/usr/bin/python3");
  m.def(
      "_validate_mls",
      [](const std::vector<std::string>& files, const std::vector<std::string>& overrides,
         double tight_factor) {
        nlohmann::json rows;
        {
          py::gil_scoped_release free;
          rows = validate_mls(files, overrides, tight_factor);
        }
        emit_log(kCallerOfWrapper);
        return to_python(rows);
      },
      py::arg("scene_files"), py::arg("overrides") = std::vector<std::string>{},
      py::arg("tight_factor") = 1.0);
}

}  // namespace vascsim::python
