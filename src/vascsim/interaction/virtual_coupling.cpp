#include "vascsim/interaction/virtual_coupling.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {
void require_positive(double value, const char* name) {
  if (!(std::isfinite(value) && value > 0.0))
    throw InputError(fmt::format("virtual coupling: {} = {} must be a positive finite number", name, value));
}
}  // namespace

double VirtualCoupling::stability_number(double mass_kg, double stiffness_n_per_m, double damping_n_s_per_m,
                                         double contact_stiffness_n_per_m, double time_step_s) {
  const double h = time_step_s;
  return (h * h * (stiffness_n_per_m + contact_stiffness_n_per_m) + 2.0 * h * damping_n_s_per_m) / mass_kg;
}

VirtualCoupling::VirtualCoupling(const VirtualCouplingSettings& settings) : settings_(settings) {
  require_positive(settings_.proxy_mass_kg, "proxy_mass_kg");
  require_positive(settings_.stiffness_n_per_m, "stiffness_n_per_m");
  require_positive(settings_.time_step_s, "time_step_s");
  if (!(std::isfinite(settings_.max_contact_stiffness_n_per_m) &&
        settings_.max_contact_stiffness_n_per_m >= 0.0))
    throw InputError(
        fmt::format("virtual coupling: max_contact_stiffness_n_per_m = {} must be finite and >= 0",
                    settings_.max_contact_stiffness_n_per_m));
  damping_ = settings_.damping_n_s_per_m < 0.0
                 ? 2.0 * std::sqrt(settings_.proxy_mass_kg * settings_.stiffness_n_per_m)
                 : settings_.damping_n_s_per_m;
  require_positive(damping_, "damping_n_s_per_m");

  const double s = stability_number(settings_.proxy_mass_kg, settings_.stiffness_n_per_m, damping_,
                                    settings_.max_contact_stiffness_n_per_m, settings_.time_step_s);
  if (!(s < 4.0)) {
    // The smallest stable mass for these stiffnesses: S is proportional to 1/m.
    throw InputError(fmt::format(
        "virtual coupling: unstable at a {} ms tick: h^2 (ks + kc_max)/m + 2 h kd/m = {:.3g} must be < 4 "
        "(m = {} kg, ks = {} N/m, kd = {:.4g} N s/m, kc_max = {} N/m); raise proxy_mass_kg above {:.3g} kg "
        "or lower the stiffnesses",
        settings_.time_step_s * 1e3, s, settings_.proxy_mass_kg, settings_.stiffness_n_per_m, damping_,
        settings_.max_contact_stiffness_n_per_m, settings_.proxy_mass_kg * s / 4.0));
  }
}

void VirtualCoupling::reset(const Vec3& position_m) {
  position_ = position_m;
  velocity_.setZero();
  contact_force_.setZero();
  initialised_ = true;
}

Vec3 VirtualCoupling::step(const Vec3& device_position_m, const ContactState& contact) {
  if (!device_position_m.allFinite()) return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  if (!initialised_) reset(device_position_m);

  // Cap the contact stiffness: trace(K) >= its largest eigenvalue for a PSD K, so scaling the trace
  // down to kc_max keeps every direction within the bound checked at construction.
  const double trace =
      contact.stiffness_n_per_m[0] + contact.stiffness_n_per_m[4] + contact.stiffness_n_per_m[8];
  const double kc_max = settings_.max_contact_stiffness_n_per_m;
  const double scale = trace > kc_max ? kc_max / trace : 1.0;
  contact_force_ = contact.force_at(position_, scale);
  if (!contact_force_.allFinite()) {
    contact_force_.setZero();
    ++recoveries_;
  }

  const double h = settings_.time_step_s;
  const double ks = settings_.stiffness_n_per_m;
  const Vec3 force = ks * (device_position_m - position_) - damping_ * velocity_ + contact_force_;
  velocity_ += (h / settings_.proxy_mass_kg) * force;
  position_ += h * velocity_;
  if (!position_.allFinite() || !velocity_.allFinite()) {
    reset(device_position_m);
    ++recoveries_;
  }
  return ks * (position_ - device_position_m);
}

}  // namespace vascsim
