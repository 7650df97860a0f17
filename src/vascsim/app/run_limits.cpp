#include "vascsim/app/run_limits.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "vascsim/core/error.hpp"
#include "vascsim/experiments/run_assessment.hpp"

namespace vascsim {

BuildChecks node_limit(const Scene& scene, bool yes) {
  BuildChecks checks;
  checks.after_body = [&scene, yes](const Body& body) {
    const Vec3Array& x = body.cloud.positions;
    if (yes || x.size() <= kMaxNodesUnasked) return;
    Vec3 lo = x.front(), hi = x.front();
    for (const Vec3& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const Vec3 span = hi - lo;
    throw InputError(
        fmt::format("{}: the body has {} nodes (it spans {:.3g} x {:.3g} x {:.3g} m), more than the {} a run "
                    "starts without "
                    "asking: check that every length is in metres (keys ending in _m) and "
                    "geometry.node_spacing_m, or pass "
                    "--yes to go ahead",
                    scene.file, x.size(), span.x(), span.y(), span.z(), kMaxNodesUnasked));
  };
  return checks;
}

void announce_run(const Scene& scene, Simulation& sim, double steps, bool yes, bool wall_clock) {
  if (const ForceAccuracyTable* table = bundled_force_accuracy())
    for (const std::string& w : model_accuracy_warnings(*table, scene, sim)) spdlog::warn("{}", w);
  const CostCalibration* calibration = bundled_cost_calibration();
  if (calibration == nullptr) return;
  const std::optional<CostEstimate> cost = estimate_run_cost(*calibration, scene, sim, steps);
  if (!cost) {
    spdlog::debug("no cost calibration for model '{}' ({})", scene.model, calibration->file.string());
    return;
  }
  if (wall_clock) {
    spdlog::info(
        "expected time per {} on this machine: {} (within a factor {:.2g} either way); the session runs in "
        "wall-clock time",
        cost->step, human_duration(cost->seconds_per_step), cost->factor);
    return;
  }
  spdlog::info("expected time on this machine: {}", describe_cost(*cost));
  if (yes || cost->total_s <= kMaxSecondsUnasked) return;
  throw InputError(fmt::format(
      "{}: this run is expected to take {} ({}), more than the {} a run starts without "
      "asking: pass --yes to go ahead, or coarsen geometry.node_spacing_m or shorten the run",
      scene.file, human_duration(cost->total_s), describe_cost(*cost), human_duration(kMaxSecondsUnasked)));
}

}  // namespace vascsim
