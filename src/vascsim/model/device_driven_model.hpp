#pragma once
// The narrow interface through which a device drives a model (the haptic session, the viewer): the tool's
// pose goes in, one frame of simulated time passes, the tool's load and the wall's linearised response come
// out. Drivers use only this; which model is behind it is the scene's choice (registry.hpp).

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "vascsim/model/model.hpp"

namespace vascsim {

/// A node in contact with the tool or about to touch it, for the haptic thread's unilateral re-solve.
struct ContactCandidate {
  Vec3 normal = Vec3::Zero();  ///< unit, out of the tool into the tissue
  double gap_m = 0.0;          ///< distance to the tool's surface (0 in contact), m
  double force_n = 0.0;        ///< normal force the tool exerts on it (0 when open), N
};

/// The tissue's linearised response to the tool around the state of the last frame.
struct ToolLinearization {
  /// dF/d(-p): how the force on the tool grows as the tool moves by -p (into the tissue), N/m, symmetric
  /// positive semi-definite. For one frictionless contact of stiffness k along normal n: k n n^T.
  Mat3 stiffness_n_per_m = Mat3::Zero();
  /// Unit contact normal from the tissue towards the tool (the direction the tissue pushes); zero when there
  /// is no single normal.
  Vec3 normal = Vec3::Zero();
  /// Contacts and near contacts with their compliance W (m/N; W_cd: normal displacement at c per unit normal
  /// force at d), so contacts can open and close between frames; empty when the model has none.
  std::vector<ContactCandidate> candidates;
  Eigen::MatrixXd compliance_m_per_n;
};

class DeviceDrivenModel {
 public:
  virtual ~DeviceDrivenModel() = default;
  /// Poses tool `tool` (an index into Problem::tools()) for the end of the next frame: its tool point moves
  /// to `position_m` and it is rotated by `orientation` (rigid_obstacle.hpp obstacle_posed). From the first
  /// call on, the tool ignores its load-factor motion. Throws std::out_of_range for a bad index.
  virtual void set_tool_pose(std::size_t tool, const Vec3& position_m,
                             const Eigen::Quaterniond& orientation) = 0;
  /// Advances one frame of frame_length_s() simulated time.
  virtual StepReport step() = 0;
  /// Simulated time at the end of the last frame, s.
  virtual double time() const = 0;
  /// Simulated time per frame, s.
  virtual double frame_length_s() const = 0;
  /// Per tool, the load it exchanged with the tissue in the last frame (the force it exerts on the tissue).
  virtual std::vector<ObstacleLoad> tool_loads() const = 0;
  /// Where tool `tool`'s point was in the last frame, m, when the model may trail the pose it was given (a
  /// real-time model follows a fast device in bounded steps); nullopt: at the pose given. The driver reports
  /// the force with this position, so the haptic thread extrapolates from where the force belongs.
  virtual std::optional<Vec3> tool_position_used(std::size_t /*tool*/) const { return std::nullopt; }
  /// Where tool `tool`'s point was in the last frame's solve, m (the device's pose unless the model trails
  /// it); tool_position_used may differ when the last frame's force is not its own (a real-time frame that
  /// ended far from equilibrium hands on the last equilibrium's force with that equilibrium's pose). nullopt:
  /// at the pose.
  virtual std::optional<Vec3> tool_position_solved(std::size_t /*tool*/) const { return std::nullopt; }
  /// The wall's linearised response at tool `tool` after the last frame, when the model computes one;
  /// nullopt: the driver estimates it (a secant along the contact normal).
  virtual std::optional<ToolLinearization> tool_linearization(std::size_t /*tool*/) const {
    return std::nullopt;
  }
  /// A realtime driver (wall-clock haptic session, viewer) lets the model trade determinism for latency: time
  /// budgets per frame, background refactorisation. Off by default: every frame is then a deterministic
  /// function of the inputs, so lockstep sessions replay bit for bit.
  virtual void set_realtime(bool /*realtime*/) {}
};

}  // namespace vascsim
