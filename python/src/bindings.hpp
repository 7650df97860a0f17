#pragma once
// The parts of the Python module _vascsim (module.cpp), one file each.

#include <pybind11/pybind11.h>

namespace vascsim::python {

/// version, build_info, models, threads, log level (module.cpp).
void bind_library(pybind11::module_& m);
/// Scene, load and parse (scene_bindings.cpp).
void bind_scene(pybind11::module_& m);
/// Simulation (simulation_bindings.cpp).
void bind_simulation(pybind11::module_& m);
/// run, force_displacement, compare_models, validate_mls (experiment_bindings.cpp).
void bind_experiments(pybind11::module_& m);

}  // namespace vascsim::python
