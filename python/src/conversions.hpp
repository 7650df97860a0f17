#pragma once
// Conversions between the library's values and Python's: JSON documents as Python objects, node arrays as
// NumPy arrays (views without a copy where the memory outlives the array), step records as dicts.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

#include "vascsim/run/simulation.hpp"

namespace vascsim::python {

namespace py = pybind11;

/// A JSON document as Python's json.loads gives it (dict, list, float, ...).
py::object to_python(const nlohmann::json& doc);

/// A read-only (n, 3) float64 view of `points` (no copy); `owner` keeps their memory alive.
py::array view_of(const Vec3Array& points, py::handle owner);

/// An (n, 3) float64 array that owns `points` (moved, not copied).
py::array array_of(Vec3Array&& points);

/// A 3-vector as a new float64 array of shape (3,).
py::array vec3(const Vec3& v);

/// One output point of `scene` as a dict with summary.json's names: step, time_s, load_factor, iterations,
/// inner_iterations, residual, converged, wall_s, regions {name: {displacement_m, force_n, force_vector_n}},
/// probes {name: m} and tools {name: {displacement_m, force_n, force_vector_n, torque_vector_n_m, contacts}}.
/// Forces are those the supports or tools exert on the tissue, N: force_n the scalar along the region's
/// direction or the tool's motion (RegionMeasure/ObstacleMeasure::force_n), force_vector_n the (3,) vector.
py::dict record_to_dict(const Scene& scene, const StepRecord& record);

}  // namespace vascsim::python
