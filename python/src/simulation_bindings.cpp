// vascsim.Simulation: a scene assembled into its model (run/simulation.hpp), driven from Python by output
// points (advance, solve: load steps or output intervals) or, for a device-driven model, by frames with a
// tool pose (set_tool_pose, step: model/device_driven_model.hpp). Node positions are read-only NumPy views
// without a copy per read; every call that moves the model copies its positions into the one buffer those
// views show (models may swap their own buffers, which would leave a view of them dangling). What the library
// logs reaches Python after every call (log_bridge.hpp): warnings as VascsimWarning, an INFO record per
// output point.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <spdlog/spdlog.h>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>

#include "bindings.hpp"
#include "conversions.hpp"
#include "log_bridge.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/run_findings.hpp"
#include "vascsim/run/tool_reach.hpp"

namespace vascsim::python {

namespace {

Scene with_model(const Scene& scene, const std::string& model) {
  if (model.empty() || model == scene.model) return scene;
  nlohmann::json doc = scene.resolved;
  doc["model"] = model;
  return parse_scene(doc, scene.file);
}

// The tools whose scripted motion never reaches the body (as run_scene warns before its first step); not for
// a device-driven use (set_tool_pose), where the scripted motion is not followed.
void log_tool_reach_warnings(const Scene& scene, const Simulation& sim) {
  for (std::size_t o = 0; o < scene.obstacles.size(); ++o) {
    const ToolReach reach = tool_reach_by_load(scene.obstacles[o], sim.discretization().rest_positions());
    if (!reach.touches()) spdlog::warn("{}", tool_reach_warning(reach, scene.obstacles[o], o));
  }
}

class PySimulation {
 public:
  PySimulation(const Scene& scene, const std::string& model)
      : sim_(with_model(scene, model)),
        positions_(sim_.model().positions()),
        last_(sim_.initial_record()),
        findings_(sim_.scene(), sim_.body()) {
    log_accuracy_warnings(sim_.scene(), sim_);
    findings_.add(last_);
  }

  const Scene& scene() const { return sim_.scene(); }
  Simulation& sim() { return sim_; }
  const Vec3Array& positions() const { return positions_; }
  int steps_done() const { return next_output_ - 1; }
  int frames_done() const { return frames_; }
  const StepRecord& last() const { return last_; }
  double total_wall_s() const { return total_wall_s_; }

  StepRecord advance() {
    const int total = sim_.model().num_steps();
    if (next_output_ > total)
      throw py::value_error(fmt::format("all {} output points of '{}' are done", total, scene().name));
    StepRecord r;
    {
      py::gil_scoped_release free;
      if (next_output_ == 1) log_tool_reach_warnings(scene(), sim_);
      r = sim_.advance(next_output_);
    }
    ++next_output_;
    keep(r);
    findings_.add(r);
    log_step(scene().name, scene().model, r, total);
    // After the last output point, what `vascsim run` finds in a finished run (summary.json's warnings).
    if (next_output_ > total)
      for (const std::string& w : findings_.warnings(total)) spdlog::warn("{}", w);
    emit_log();
    return r;
  }

  StepRecord step() {
    DeviceDrivenModel& d = device_driven("step");
    StepRecord r;
    {
      py::gil_scoped_release free;
      const auto t0 = std::chrono::steady_clock::now();
      const StepReport rep = d.step();
      r = sim_.measure(frames_ + 1, rep);
      r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    ++frames_;
    keep(r);
    emit_log();
    return r;
  }

  void set_tool_pose(const Vec3& position_m, const std::optional<std::array<double, 4>>& wxyz,
                     const py::object& tool) {
    DeviceDrivenModel& d = device_driven("set_tool_pose");
    const std::size_t t = tool_index(tool);
    if (!position_m.allFinite()) throw InputError("set_tool_pose: the position must be finite (m)");
    Eigen::Quaterniond q = rest_orientation(scene().obstacles[t]);
    if (wxyz) {
      q = Eigen::Quaterniond((*wxyz)[0], (*wxyz)[1], (*wxyz)[2], (*wxyz)[3]);
      if (!q.coeffs().allFinite() || !(q.norm() > 0.0))
        throw InputError("set_tool_pose: the orientation must be a finite, non-zero quaternion (w, x, y, z)");
      q.normalize();
    }
    d.set_tool_pose(t, position_m, q);
  }

  DeviceDrivenModel& device_driven(const char* what) {
    DeviceDrivenModel* d = sim_.model().device_driven();
    if (!d)
      throw InputError(fmt::format("{}: model '{}' cannot be driven by a device; use one of: {}", what,
                                   scene().model,
                                   fmt::join(model_names_with(&ModelCapabilities::device_driven), ", ")));
    return *d;
  }

  std::size_t tool_index(const py::object& tool) const {
    if (tool.is_none()) return find_tool(scene(), "", "tool");
    if (py::isinstance<py::str>(tool)) return find_tool(scene(), tool.cast<std::string>(), "tool");
    const long i = tool.cast<long>();
    if (i < 0 || static_cast<std::size_t>(i) >= scene().obstacles.size())
      throw InputError(fmt::format("{}: tool {} does not exist (the scene has {} tools)", scene().file, i,
                                   scene().obstacles.size()));
    return static_cast<std::size_t>(i);
  }

 private:
  static Eigen::Quaterniond rest_orientation(const RigidObstacle& o) {
    return o.catheter ? orientation_pointing(o.a_m - o.b_m) : Eigen::Quaterniond::Identity();
  }

  void keep(const StepRecord& r) {
    const Vec3Array& x = sim_.model().positions();
    std::copy(x.begin(), x.end(), positions_.begin());  // in place: existing views stay valid
    total_wall_s_ += r.wall_s;
    last_ = r;
  }

  Simulation sim_;
  Vec3Array positions_;
  StepRecord last_;
  RunFindings findings_;  // of the output points (advance), not of device frames (step)
  int next_output_ = 1;
  int frames_ = 0;
  double total_wall_s_ = 0.0;
};

py::list solve(PySimulation& s, const py::object& on_step) {
  py::list records;
  while (s.steps_done() < s.sim().model().num_steps()) {
    py::dict r = record_to_dict(s.scene(), s.advance());
    if (!on_step.is_none()) on_step(r);
    records.append(r);
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C between output points
  }
  return records;
}

py::dict surface(PySimulation& s, py::handle self) {
  SurfaceFrame f = s.sim().surface_frame();
  emit_log();  // the surface map logs what it built the first time
  const auto& tris = s.sim().body().surface->triangles;
  py::dict d;
  d["vertices"] = array_of(std::move(f.positions));
  d["normals"] = array_of(std::move(f.normals));
  d["displacements"] = array_of(std::move(f.displacements));
  static_assert(sizeof(std::array<Index, 3>) == 3 * sizeof(Index), "triangles must be packed to be viewed");
  py::array t(
      py::dtype::of<Index>(), {static_cast<py::ssize_t>(tris.size()), py::ssize_t{3}},
      {static_cast<py::ssize_t>(sizeof(std::array<Index, 3>)), static_cast<py::ssize_t>(sizeof(Index))},
      tris.empty() ? nullptr : tris.front().data(), self);
  t.attr("setflags")(py::arg("write") = false);
  d["triangles"] = t;
  return d;
}

py::list tool_loads(PySimulation& s) {
  const Scene& scene = s.scene();
  Model& model = s.sim().model();
  DeviceDrivenModel* d = model.device_driven();
  const std::vector<ObstacleLoad> loads = d ? d->tool_loads() : model.obstacle_loads();
  py::list out;
  for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
    const ObstacleLoad l = i < loads.size() ? loads[i] : ObstacleLoad{};
    py::dict t;
    t["name"] = scene.obstacles[i].name;
    t["force_vector_n"] = vec3(l.force_vector_n);
    t["torque_vector_n_m"] = vec3(l.torque_vector_n_m);
    t["contacts"] = l.contacts;
    if (d)
      if (const std::optional<Vec3> p = d->tool_position_used(i)) t["position_used_m"] = vec3(*p);
    out.append(t);
  }
  return out;
}

py::dict statistics(PySimulation& s) {
  py::dict d = record_to_dict(s.scene(), s.last());
  d.attr("pop")("regions");
  d.attr("pop")("probes");
  d.attr("pop")("tools");
  d["model"] = s.scene().model;
  d["nodes"] = s.sim().discretization().num_nodes();
  d["setup_s"] = s.sim().setup_seconds();
  d["steps_done"] = s.steps_done();
  d["frames_done"] = s.frames_done();
  d["total_wall_s"] = s.total_wall_s();
  d["info"] = to_python(s.sim().model().info());
  return d;
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<PySimulation>(m, "Simulation", R"(A scene assembled into its model (SI units: m, N, s).

Simulation(scene, model=None): model, when given, replaces the scene's (as --set model=NAME, validated again).
Not thread-safe: use one Simulation from one thread at a time (different Simulations may run in different
threads; the GIL is released while the model computes).

A record (advance, solve, step, last_record) is a dict with the names and meanings of summary.json's steps:
step, time_s (s), load_factor (1), iterations, inner_iterations, residual (1), converged, wall_s (s, wall
clock), probes {name: displacement, m}, and
  regions {name: {displacement_m (m), force_n (N, scalar), force_vector_n ((3,) N)}}: the force the supports
    exert on the tissue (a fixed or displaced region) or the force applied to it (a force region); force_n is
    force_vector_n projected on the region's direction, its magnitude for a region without one;
  tools {name: {displacement_m (m, the tool's travel), force_n (N, scalar), force_vector_n ((3,) N),
    torque_vector_n_m ((3,) N m, about the tool point), contacts}}: the force the tool exerts on the tissue
    (the tissue pushes the tool with -force_vector_n); force_n is its component along the tool's motion
    (positive while the tool presses), its magnitude for a tool that does not move.

Progress: an INFO record per output point on the logger "vascsim" of Python's logging
(logging.basicConfig(level=logging.INFO) shows them). Warnings (what the command line prints: the scene's and
the model's accuracy at these settings when built, a tool whose motion never reaches the tissue at the first
advance, inverted material under a tool) are issued through warnings.warn as vascsim.VascsimWarning.)")
      .def(py::init([](const Scene& scene, const std::optional<std::string>& model) {
             std::unique_ptr<PySimulation> s;
             {
               py::gil_scoped_release free;
               s = std::make_unique<PySimulation>(scene, model.value_or(""));
             }
             emit_log();
             return s;
           }),
           py::arg("scene"), py::arg("model") = py::none())
      .def_property_readonly("scene", &PySimulation::scene, "The scene it runs (with the model chosen).")
      .def_property_readonly(
          "model", [](PySimulation& s) { return s.scene().model; }, "The model's registry name.")
      .def_property_readonly("num_nodes",
                             [](PySimulation& s) { return s.sim().discretization().num_nodes(); })
      .def_property_readonly(
          "num_steps", [](PySimulation& s) { return s.sim().model().num_steps(); },
          "Output points of the scene (load steps, or output intervals of a dynamic model).")
      .def_property_readonly("steps_done", &PySimulation::steps_done, "Output points advanced so far.")
      .def_property_readonly("frames_done", &PySimulation::frames_done,
                             "Device-driven frames stepped so far.")
      .def_property_readonly(
          "device_driven", [](PySimulation& s) { return s.sim().model().device_driven() != nullptr; },
          "True when set_tool_pose and step work (the model's registry capability).")
      .def_property_readonly(
          "time_s",
          [](PySimulation& s) {
            DeviceDrivenModel* d = s.sim().model().device_driven();
            return d && s.frames_done() > 0 ? d->time() : s.last().report.time_s;
          },
          "Simulated time at the last output point or frame, s.")
      .def_property_readonly(
          "frame_length_s",
          [](PySimulation& s) { return s.device_driven("frame_length_s").frame_length_s(); },
          "Simulated time per step() frame, s (device-driven models).")
      .def(
          "advance", [](PySimulation& s) { return record_to_dict(s.scene(), s.advance()); },
          "Advances to the next output point and returns its record (see Simulation: forces in N on the "
          "tissue, "
          "displacements in m).")
      .def("solve", &solve, py::arg("on_step") = py::none(),
           "Advances through every remaining output point; returns their records. on_step(record) is called "
           "after "
           "each (and an INFO record logged on the logger \"vascsim\"); Ctrl-C stops between output points.")
      .def(
          "step", [](PySimulation& s) { return record_to_dict(s.scene(), s.step()); },
          "One frame of frame_length_s of a device-driven model with the last tool pose; returns its record.")
      .def("set_tool_pose", &PySimulation::set_tool_pose, py::arg("position_m"),
           py::arg("orientation") = py::none(), py::arg("tool") = py::none(),
           "Poses a tool for the next step(): its tool point (a catheter's tip) at position_m (m, scene "
           "frame), "
           "rotated by orientation (a unit quaternion w, x, y, z mapping the tool frame, whose -z the tool "
           "points "
           "along, to the scene; default: the tool's rest orientation). tool: name or index (default: the "
           "only "
           "tool). From the first call on, the tool ignores its scripted motion.")
      .def_property_readonly(
          "positions", [](py::object self) { return view_of(self.cast<PySimulation&>().positions(), self); },
          "Node positions (N, 3), m: a read-only view, updated in place by every advance() and step().")
      .def_property_readonly(
          "rest_positions",
          [](py::object self) {
            return view_of(self.cast<PySimulation&>().sim().discretization().rest_positions(), self);
          },
          "Node rest positions (N, 3), m: a read-only view.")
      .def(
          "surface", [](py::object self) { return surface(self.cast<PySimulation&>(), self); },
          "The render surface mapped from the nodes by the MLS map (built on first call): a dict of vertices "
          "(V, 3) m, normals (V, 3) unit, displacements (V, 3) m and triangles (T, 3) vertex indices (a "
          "read-only "
          "view).")
      .def("tool_loads", &tool_loads,
           "Per tool (scene order): name, force_vector_n (3,) the force it exerts on the tissue now (N; the "
           "tissue "
           "pushes the tool with -force_vector_n), torque_vector_n_m (3,) about the tool point (N m), "
           "contacts, and "
           "for a model that trails its device position_used_m (m).")
      .def_property_readonly(
          "statistics", &statistics,
          "The solver's statistics: the last record's report (iterations, inner_iterations, "
          "residual, converged, wall_s), steps and frames done, total wall time (s), setup time "
          "(s), node count and the model's info() (its parameters and running totals).")
      .def_property_readonly(
          "last_record", [](PySimulation& s) { return record_to_dict(s.scene(), s.last()); },
          "The record of the last output point or frame (the rest state before any).");
}

}  // namespace vascsim::python
