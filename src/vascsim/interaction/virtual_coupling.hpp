#pragma once
// The virtual-coupling controller of the haptic loop (docs/haptics.md). A tool proxy of mass m follows
// the device position d through a spring ks; a damper kd acts on the proxy velocity; the extrapolated
// contact force F_c (ContactState::force_at) acts on the proxy. The device is sent the spring force on
// its side, ks (x - d): in steady contact this equals the contact force, and in free space it is the
// small lag force of the proxy. The device is never coupled to the tissue directly, so a stiff or
// delayed simulation cannot make it buzz: what the hand feels is at most as stiff as ks.
//
// Per tick h (semi-implicit Euler, the velocity first):
//     v <- v + h/m (ks (d - x) - kd v + F_c(x)),    x <- x + h v,    F_device = ks (x - d).
// Stability: for a proxy stiffness k = ks + kc (kc: contact stiffness seen by the proxy) and damping kd,
// the update is stable iff
//     S = h^2 (ks + kc)/m + 2 h kd/m < 4      (and kd > 0 for the oscillation to decay).
// (Derivation: with a^2 = h^2 k/m, b = h kd/m the step matrix has trace 2 - a^2 - b and determinant
// 1 - b; the Jury conditions give 0 < b < 2 and a^2 + 2b < 4.) The constructor checks S with the
// largest contact stiffness it will use, max_contact_stiffness_n_per_m; at run time a contact
// stiffness K whose trace exceeds that bound is scaled down to it, so the bound holds every tick.
//
// The damper is on the proxy's own velocity, not on the difference to the device velocity: that
// avoids differentiating a quantised encoder position, and a critically damped proxy then follows a
// step of the device without overshoot. The price is a drag kd v in free motion (0.06 N at 2 cm/s with
// the defaults).

#include <cstdint>

#include "vascsim/core/types.hpp"
#include "vascsim/interaction/contact_state.hpp"

namespace vascsim {

struct VirtualCouplingSettings {
  /// Proxy mass. 5 g: small against the Omni's own apparent tip mass (tens of grams), so it adds
  /// little inertia, and large enough that the default stiffnesses are stable with margin (S = 1.57).
  double proxy_mass_kg = 0.005;
  /// Coupling spring. Half the Omni's softest renderable axis (1.02 N/mm, DeviceLimits): the hand feels
  /// at most ks in series with the tissue, so the device never renders more than it can.
  double stiffness_n_per_m = 500.0;
  /// Damper on the proxy velocity; negative means critical damping, 2 sqrt(m ks) (3.16 N s/m by
  /// default): the fastest response without overshoot.
  double damping_n_s_per_m = -1.0;
  /// Largest contact stiffness applied to the proxy between simulation updates. Tissue contact is far
  /// softer (tens of N/m for a vein), so 1 N/mm only caps a pathological linearisation.
  double max_contact_stiffness_n_per_m = 1000.0;
  /// The tick: 1 ms for the 1 kHz loop. The proxy always steps by exactly this, also when a tick is
  /// late, so the stability bound holds and a replay is deterministic.
  double time_step_s = 1e-3;
};

class VirtualCoupling {
 public:
  /// Checks the settings (positive, finite) and the stability bound above. Throws InputError that
  /// names S and how to fix it.
  explicit VirtualCoupling(const VirtualCouplingSettings& settings = {});

  /// S = h^2 (ks + kc)/m + 2 h kd/m; the update is stable iff S < 4 (with kd > 0).
  static double stability_number(double mass_kg, double stiffness_n_per_m, double damping_n_s_per_m,
                                 double contact_stiffness_n_per_m, double time_step_s);

  /// Puts the proxy at rest at `position_m`. The first step() does this at the device position.
  void reset(const Vec3& position_m);

  /// One tick: integrates the proxy towards `device_position_m` under the coupling and the contact
  /// force contact.force_at(proxy), and returns the force to send to the device (device side, N). A
  /// non-finite device position returns NaN without touching the proxy (the output filter then sends
  /// zero and counts it); a non-finite contact force is ignored for this tick; a proxy state that still
  /// turns non-finite is reset to the device position. Both are counted in recoveries().
  Vec3 step(const Vec3& device_position_m, const ContactState& contact);

  const VirtualCouplingSettings& settings() const { return settings_; }
  double damping_n_s_per_m() const { return damping_; }
  const Vec3& proxy_position_m() const { return position_; }
  const Vec3& proxy_velocity_m_per_s() const { return velocity_; }
  /// The contact force applied to the proxy in the last step (after the stiffness cap).
  const Vec3& contact_force_n() const { return contact_force_; }
  /// Ticks in which a non-finite contact force was ignored or the proxy was reset.
  std::uint64_t recoveries() const { return recoveries_; }

 private:
  VirtualCouplingSettings settings_;
  double damping_ = 0.0;
  bool initialised_ = false;
  Vec3 position_ = Vec3::Zero();
  Vec3 velocity_ = Vec3::Zero();
  Vec3 contact_force_ = Vec3::Zero();
  std::uint64_t recoveries_ = 0;
};

}  // namespace vascsim
