#pragma once
// The simulation side of a haptic session (docs/haptics.md): each frame it poses the tool from the haptic
// thread's latest ToolPose, steps the device-driven model, and publishes the contact force on the tool with
// the wall's linearised response (ContactState), so the 1 kHz loop can follow the tool between frames.
//
// The linearisation comes from the model when it computes one (DeviceDrivenModel::tool_linearization);
// otherwise from a secant of the force magnitude along the contact normal between consecutive frames,
// clamped to [0, max_stiffness].

#include "vascsim/interaction/contact_state.hpp"
#include "vascsim/interaction/latest_value.hpp"
#include "vascsim/model/device_driven_model.hpp"

namespace vascsim {

/// One frame as force_history.csv records it.
struct FrameSample {
  double sim_time_s = 0.0, pose_time_s = 0.0;
  /// Where the frame's force belongs (the pose it hands to the haptic thread), m: the frame's own tool pose,
  /// or the last equilibrium's when the frame ended far from its own
  /// (ImplicitModel::Settings::handoff_max_residual).
  Vec3 tool_position_m = Vec3::Zero();
  Vec3 pose_position_m = Vec3::Zero();  ///< the device pose the frame was given, m
  double tool_lag_m = 0.0;         ///< how far the model's tool was from that pose in the frame's solve, m
  Vec3 force_n = Vec3::Zero();     ///< the force the tissue exerts on the tool, N
  Vec3 torque_n_m = Vec3::Zero();  ///< its moment about the tool point, N m
  int contacts = 0;
  double residual = 0.0;  ///< relative force residual the frame reached (0 for models without one)
  bool converged = true;  ///< the frame reached its tolerance
  double wall_s = 0.0;    ///< wall-clock time of the frame, s
};

class ContactPublisher {
 public:
  /// `tool`: index into the problem's tools; `force_scale`: device force per tool force (scaled feedback for
  /// tiny vessels); `max_stiffness_n_per_m`: the most the secant estimate may report.
  ContactPublisher(DeviceDrivenModel& model, std::size_t tool, double force_scale,
                   double max_stiffness_n_per_m, LatestValue<ContactState>& to_haptics);

  /// Poses the tool, steps the model one frame, publishes the contact state; returns the frame's record.
  FrameSample step(const ToolPose& pose);

 private:
  void publish(const ToolPose& pose, const Vec3& force_on_tool);
  Mat3 secant_stiffness(const ToolPose& pose, const Vec3& force_on_tool, Vec3& normal);

  DeviceDrivenModel& model_;
  std::size_t tool_;
  double scale_, max_k_;
  LatestValue<ContactState>& out_;
  std::uint64_t sequence_ = 0;
  bool have_previous_ = false;
  Vec3 previous_position_ = Vec3::Zero();
  double previous_magnitude_ = 0.0, k_ = 0.0;
};

}  // namespace vascsim
