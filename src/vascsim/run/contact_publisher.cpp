#include "vascsim/run/contact_publisher.hpp"

#include <algorithm>
#include <cmath>

#include "vascsim/core/stopwatch.hpp"

namespace vascsim {

ContactPublisher::ContactPublisher(DeviceDrivenModel& model, std::size_t tool, double force_scale,
                                   double max_stiffness_n_per_m, LatestValue<ContactState>& to_haptics)
    : model_(model), tool_(tool), scale_(force_scale), max_k_(max_stiffness_n_per_m), out_(to_haptics) {}

FrameSample ContactPublisher::step(const ToolPose& pose) {
  const Stopwatch clock;
  model_.set_tool_pose(tool_, pose.position(), pose.orientation());
  const StepReport report = model_.step();
  const ObstacleLoad load = model_.tool_loads()[tool_];
  // The force belongs to where the model had the tool (a real-time model may trail a fast device).
  ToolPose used = pose;
  if (const auto p = model_.tool_position_used(tool_)) used.set_position(*p);
  FrameSample s;
  s.sim_time_s = model_.time();
  s.pose_time_s = pose.time_s;
  s.tool_position_m = used.position();
  s.pose_position_m = pose.position();
  if (const auto p = model_.tool_position_solved(tool_)) s.tool_lag_m = (*p - pose.position()).norm();
  s.force_n = -load.force_vector_n;  // the tissue's force on the tool
  s.torque_n_m = -load.torque_vector_n_m;
  s.contacts = load.contacts;
  s.residual = report.residual;
  s.converged = report.converged;
  publish(used, scale_ * s.force_n);
  s.wall_s = clock.seconds();
  return s;
}

Mat3 ContactPublisher::secant_stiffness(const ToolPose& pose, const Vec3& f, Vec3& n) {
  const double magnitude = f.norm();
  n = magnitude > 0.0 ? Vec3(f / magnitude) : Vec3::Zero();
  if (magnitude == 0.0) {
    k_ = 0.0;
  } else if (have_previous_) {
    // Secant along the normal: moving into the tissue (along -n) raises |F|.
    const double dx = (pose.position() - previous_position_).dot(n);
    if (std::abs(dx) > 1e-7) k_ = std::clamp(-(magnitude - previous_magnitude_) / dx, 0.0, max_k_);
  }
  have_previous_ = true;
  previous_position_ = pose.position();
  previous_magnitude_ = magnitude;
  return normal_stiffness(n, k_);
}

void ContactPublisher::publish(const ToolPose& pose, const Vec3& f) {
  ContactState c;
  c.sequence = ++sequence_;
  c.sim_time_s = model_.time();
  c.tool = pose;
  c.set_force(f);
  if (const auto lin = model_.tool_linearization(tool_)) {
    c.set_stiffness(scale_ * lin->stiffness_n_per_m);
    c.set_normal(lin->normal);
    // Candidate contacts in device units: forces scale by the feedback scale, compliances by its inverse.
    const int m = std::min<int>(static_cast<int>(lin->candidates.size()), ContactState::kMaxCandidates);
    c.candidates = scale_ > 0.0 ? m : 0;
    for (int i = 0; i < c.candidates; ++i) {
      const ContactCandidate& k = lin->candidates[static_cast<std::size_t>(i)];
      c.set_candidate(i, k.normal, k.gap_m, scale_ * k.force_n);
      for (int j = 0; j < m; ++j) c.compliance(i, j) = lin->compliance_m_per_n(i, j) / scale_;
    }
  } else {
    Vec3 n;
    c.set_stiffness(secant_stiffness(pose, f, n));
    c.set_normal(n);
  }
  out_.write(c);
}

}  // namespace vascsim
