#include "vascsim/run/haptic_rig.hpp"

#include <fmt/format.h>
#include <algorithm>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

DeviceLimits capped_limits(const Device& device, const HapticsSpec& spec) {
  DeviceLimits l = device.limits();
  l.max_continuous_force_n = std::min(l.max_continuous_force_n, spec.force_limit_n);
  return l;
}

VirtualCoupling coupling_for(const HapticsSpec& spec, const DeviceLimits& limits) {
  VirtualCouplingSettings cs;
  cs.proxy_mass_kg = spec.proxy_mass_kg;
  cs.stiffness_n_per_m = spec.coupling_stiffness_n_per_m;
  cs.damping_n_s_per_m = spec.coupling_damping_n_s_per_m;
  cs.max_contact_stiffness_n_per_m = limits.max_stiffness_n_per_m;
  cs.time_step_s = 1.0 / spec.rate_hz;
  return VirtualCoupling(cs);
}

ForceOutputFilter filter_for(const HapticsSpec& spec, const DeviceLimits& limits) {
  ForceOutputSettings fo;
  fo.max_force_n = limits.max_continuous_force_n;
  fo.max_step_n_per_tick = spec.force_step_n;
  return ForceOutputFilter(fo);
}

HapticLoopOptions loop_options(const HapticsSpec& spec, const HapticRigOptions& options,
                               SessionRecording& recording) {
  HapticLoopOptions lo;
  lo.rate_hz = spec.rate_hz;
  lo.record = options.record ? &recording : nullptr;
  lo.start_time_s = options.start_time_s;
  return lo;
}

}  // namespace

DeviceDrivenModel& device_driven_model(Simulation& simulation) {
  DeviceDrivenModel* model = simulation.model().device_driven();
  if (model == nullptr)
    throw InputError(fmt::format("{}: model '{}' cannot be driven by a device", simulation.scene().file,
                                 simulation.scene().model));
  return *model;
}

DeviceLimits scripted_device_limits(const HapticsSpec& haptics) {
  DeviceLimits l;
  l.max_continuous_force_n = haptics.force_limit_n;
  l.max_peak_force_n = std::max(l.max_peak_force_n, haptics.force_limit_n);
  return l;
}

// The loop's parts check their settings (the coupling's stability, the clamp); a failure names the scene's
// keys.
HapticRig::HapticRig(DeviceDrivenModel& model, const Scene& scene, Device& device,
                     const HapticRigOptions& options) try
    : device_(device),
      tool_(options.tool),
      start_time_s_(options.start_time_s),
      period_s_(1.0 / scene.haptics.rate_hz),
      limits_(capped_limits(device, scene.haptics)),
      recording_(options.record ? options.reserve_ticks : 0),
      loop_(device, coupling_for(scene.haptics, limits_), filter_for(scene.haptics, limits_), from_sim_,
            to_sim_, loop_options(scene.haptics, options, recording_)),
      publisher_(model, options.tool, scene.haptics.force_scale, limits_.max_stiffness_n_per_m, from_sim_) {
  const DevicePose first = device.pose(options.start_time_s);
  model.set_tool_pose(tool_, first.position_m, first.orientation);
  last_pose_.time_s = first.time_s;
  last_pose_.set_position(first.position_m);
  last_pose_.set_orientation(first.orientation);
} catch (const InputError& e) {
  throw InputError(fmt::format("{}: key 'haptics' (rate_hz = {} Hz, force_limit_n = {} N, coupling): {}",
                               scene.file, scene.haptics.rate_hz, scene.haptics.force_limit_n, e.what()));
}

void HapticRig::tick_through(std::size_t k) {
  for (; next_tick_ <= k; ++next_tick_)
    loop_.tick(start_time_s_ + static_cast<double>(next_tick_) * period_s_);
}

FrameSample HapticRig::lockstep_frame(std::size_t k) {
  tick_through(k);
  to_sim_.update();
  last_pose_ = to_sim_.value();
  return publisher_.step(last_pose_);
}

bool HapticRig::realtime_frame(FrameSample& sample) {
  to_sim_.update();
  if (to_sim_.value().sequence == 0) return false;
  last_pose_ = to_sim_.value();
  sample = publisher_.step(last_pose_);
  return true;
}

}  // namespace vascsim
