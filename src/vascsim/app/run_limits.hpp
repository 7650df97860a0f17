#pragma once
// What `vascsim run` and `vascsim check` do before a large run: a body of more than kMaxNodesUnasked nodes is
// refused after it is built (before the discretisation, which is where the memory goes), and a run expected
// to take longer than kMaxSecondsUnasked (from the machine's cost calibration) is refused after its set-up,
// each with one line giving the size and the estimate, unless the user passed --yes. A length typed in mm
// where metres are expected is the usual cause.

#include "vascsim/run/simulation.hpp"

namespace vascsim {

constexpr std::size_t kMaxNodesUnasked = 200000;
constexpr double kMaxSecondsUnasked = 600.0;

/// The build check refusing a body above kMaxNodesUnasked nodes unless `yes` (an InputError naming the file,
/// the node count, the body's extent and --yes).
BuildChecks node_limit(const Scene& scene, bool yes);

/// Logs the run's expected cost and the model's known accuracy problems at these settings (warnings), and
/// refuses a run expected to take longer than kMaxSecondsUnasked unless `yes`. `steps`: the model steps the
/// run takes. Nothing but the warnings when the machine has no cost calibration for the model. A run paced by
/// the wall clock (a realtime haptic session) lasts its duration whatever its frames cost: only the expected
/// time per frame is logged.
void announce_run(const Scene& scene, Simulation& sim, double steps, bool yes, bool wall_clock = false);

}  // namespace vascsim
