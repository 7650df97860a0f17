// The compiled part of the Python package `vascsim` (python/vascsim/__init__.py wraps it; docs/api.md,
// "Python module"). Errors: InputError (bad input: a ValueError) and NumericalError (a RuntimeError) carry
// the same one-line messages as the command line.

#include <omp.h>

#include <spdlog/spdlog.h>

#include "bindings.hpp"
#include "conversions.hpp"
#include "log_bridge.hpp"
#include "vascsim/core/build_info.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/model/registry.hpp"

namespace vascsim::python {

namespace {

py::dict build_info_dict() {
  const BuildInfo b = build_info();
  py::dict d;
  d["version"] = b.version;
  d["build_type"] = b.build_type;
  d["compiler"] = b.compiler;
  d["library"] = b.library;
  d["sanitizers"] = b.sanitizers;
  d["openmp"] = b.openmp;
  d["omp_max_threads"] = b.omp_max_threads;
  d["blas"] = b.blas;
  d["cholmod"] = b.cholmod;
  d["bundled_files"] = b.bundled_files;
  return d;
}

py::list models_list() {
  py::list out;
  for (const ModelEntry& e : model_registry()) {
    py::dict d;
    d["name"] = e.name;
    d["summary"] = e.summary;
    d["dynamic"] = e.capabilities.dynamic;
    d["takes_tools"] = e.capabilities.takes_tools;
    d["device_driven"] = e.capabilities.device_driven;
    d["releases_regions"] = e.capabilities.releases_regions;
    out.append(d);
  }
  return out;
}

// The library logs through spdlog's default logger, which in Python hands its lines to Python
// (log_bridge.hpp); this level drops lines before they get there.
void set_log_level(const std::string& level) {
  const spdlog::level::level_enum l = spdlog::level::from_str(level);
  if (l == spdlog::level::off && level != "off")
    throw InputError("set_log_level: '" + level +
                     "' is not one of trace, debug, info, warn, error, critical, off");
  spdlog::set_level(l);
}

}  // namespace

void bind_library(py::module_& m) {
  m.def("version", &version, "The library's version, MAJOR.MINOR.PATCH.");
  m.def("build_info", &build_info_dict,
        "How the library was built (build type, compiler, shared or static, OpenMP) and the run-time "
        "libraries it "
        "found (BLAS, CHOLMOD), as `vascsim --version` prints them.");
  m.def("models", &models_list,
        "The registered models in registry order: name, summary and capabilities (dynamic, takes_tools, "
        "device_driven, releases_regions).");
  m.def(
      "set_threads",
      [](int n) {
        // The bound of `vascsim -j` (app/command.hpp, kMaxThreads): beyond it OpenMP may end the process.
        if (n < 1 || n > 256) throw InputError("set_threads: " + std::to_string(n) + " is outside 1..256");
        omp_set_num_threads(n);
      },
      py::arg("threads"), "OpenMP threads for the following work (as `vascsim -j`).");
  m.def(
      "threads", [] { return omp_get_max_threads(); }, "OpenMP threads a parallel region uses now.");
  m.def("set_log_level", &set_log_level, py::arg("level"),
        "The lowest level the library passes on: trace, debug, info (the default), warn, error, critical or "
        "off. "
        "Warnings arrive through warnings.warn as VascsimWarning, the other lines through Python's logging "
        "(logger "
        "\"vascsim\"), whose own level then decides what is shown.");
}

}  // namespace vascsim::python

PYBIND11_MODULE(_vascsim, m) {
  namespace vp = vascsim::python;
  m.doc() =
      "vascsim: point-primitive vascular tissue simulation (the compiled module; use the package `vascsim`).";
  pybind11::register_exception<vascsim::InputError>(m, "InputError", PyExc_ValueError);
  pybind11::register_exception<vascsim::NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  vp::bind_log(m);
  vp::bind_library(m);
  vp::bind_scene(m);
  vp::bind_simulation(m);
  vp::bind_experiments(m);
}
