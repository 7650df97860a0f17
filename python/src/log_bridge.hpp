#pragma once
// The library's log and progress in Python. spdlog's default logger queues what the library logs (from any
// thread, with or without the GIL: the sink takes no Python lock, so it cannot deadlock against a thread that
// holds the GIL), and emit_log() hands the queue to Python from a thread that holds the GIL: warnings through
// warnings.warn as vascsim.VascsimWarning (a UserWarning), the other levels to the logger "vascsim" of
// Python's logging. Progress goes to the same logger, one INFO record per output point (log_step).

#include <pybind11/pybind11.h>

#include <set>
#include <string>

#include "vascsim/run/simulation.hpp"

namespace vascsim::python {

/// Adds VascsimWarning to `m` and makes spdlog's default logger queue for emit_log (at level info: Python's
/// logging decides what is shown).
void bind_log(pybind11::module_& m);

/// Issues `text` through warnings.warn as VascsimWarning; needs the GIL. `stacklevel` as for warnings.warn: 1
/// names the Python line that called into the module, 2 its caller (for the package's wrappers in
/// vascsim/__init__.py). Throws pybind11::error_already_set when the warnings filter turns it into an error.
void warn(const std::string& text, int stacklevel = 1);

/// Hands what the library logged since the last call to Python (warnings through warn()); needs the GIL. Adds
/// the warnings' texts to `warned` if given. Throws as warn().
void emit_log(int stacklevel = 1, std::set<std::string>* warned = nullptr);

/// "<label>: step k of n: <status> (<wall> s)" at INFO on the logger "vascsim", with the status line of the
/// command line's progress for `model` (app/step_status.hpp); needs the GIL.
void log_step(const std::string& label, const std::string& model, const StepRecord& record, int total);

/// Logs what `vascsim run` warns of once a run is built (announce_run): the scene's own warnings and the
/// model's accuracy at these settings (experiments/run_assessment.hpp). Needs no GIL.
void log_accuracy_warnings(const Scene& scene, Simulation& sim);

}  // namespace vascsim::python
