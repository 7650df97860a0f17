#include "conversions.hpp"

namespace vascsim::python {

py::object to_python(const nlohmann::json& doc) {
  return py::module_::import("json").attr("loads")(doc.dump());
}

namespace {

// An (n, 3) float64 array over `points` (no copy) whose memory `owner` keeps alive; writeable.
py::array wrap(const Vec3Array& points, py::handle owner) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles to be viewed");
  const auto n = static_cast<py::ssize_t>(points.size());
  return py::array(py::dtype::of<double>(), {n, py::ssize_t{3}},
                   {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
                   points.empty() ? nullptr : points.front().data(), owner);
}

}  // namespace

py::array view_of(const Vec3Array& points, py::handle owner) {
  py::array a = wrap(points, owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::array array_of(Vec3Array&& points) {
  auto* held = new Vec3Array(std::move(points));
  py::capsule owner(held, [](void* p) { delete static_cast<Vec3Array*>(p); });
  return wrap(*held, owner);  // the caller's own array
}

py::array vec3(const Vec3& v) {
  py::array_t<double> a(3);
  for (py::ssize_t i = 0; i < 3; ++i) a.mutable_at(i) = v[i];
  return a;
}

py::dict record_to_dict(const Scene& scene, const StepRecord& r) {
  py::dict d;
  d["step"] = r.step;
  d["time_s"] = r.report.time_s;
  d["load_factor"] = r.report.load_factor;
  d["iterations"] = r.report.iterations;
  d["inner_iterations"] = r.report.inner_iterations;
  d["residual"] = r.report.residual;
  d["converged"] = r.report.converged;
  d["wall_s"] = r.wall_s;
  py::dict regions, probes, tools;
  for (std::size_t i = 0; i < r.regions.size() && i < scene.regions.size(); ++i) {
    const RegionMeasure& m = r.regions[i];
    regions[py::str(scene.regions[i].name)] =
        py::dict(py::arg("displacement_m") = m.displacement_m, py::arg("force_n") = m.force_n,
                 py::arg("force_vector_n") = vec3(m.force_vector_n));
  }
  for (std::size_t i = 0; i < r.probes.size() && i < scene.probes.size(); ++i)
    probes[py::str(scene.probes[i].name)] = r.probes[i];
  for (std::size_t i = 0; i < r.obstacles.size() && i < scene.obstacles.size(); ++i) {
    const ObstacleMeasure& m = r.obstacles[i];
    tools[py::str(scene.obstacles[i].name)] =
        py::dict(py::arg("displacement_m") = m.displacement_m, py::arg("force_n") = m.force_n,
                 py::arg("force_vector_n") = vec3(m.force_vector_n),
                 py::arg("torque_vector_n_m") = vec3(m.torque_vector_n_m), py::arg("contacts") = m.contacts);
  }
  // The names and meanings of summary.json's steps (run/runner.cpp, step_json): force_n the scalar,
  // force_vector_n the vector, both on the tissue.
  d["regions"] = regions;
  d["probes"] = probes;
  d["tools"] = tools;
  return d;
}

}  // namespace vascsim::python
