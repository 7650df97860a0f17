#pragma once
// The cross-section of a flexible instrument (guidewire, catheter) and the stiffnesses a rod model needs
// (docs/model/26-rod.md): a solid circle (a wire) or an annulus (a catheter's tube), of one linear elastic
// material. SI units throughout.

#include "vascsim/core/types.hpp"

namespace vascsim::rod {

struct RodSection {
  double outer_diameter_m = 0.0;   ///< > 0
  double inner_diameter_m = 0.0;   ///< 0 for a solid wire, otherwise < outer_diameter_m (a tube)
  double youngs_modulus_pa = 0.0;  ///< E, > 0
  double shear_modulus_pa = 0.0;   ///< G, > 0 (E / (2 (1 + nu)) for an isotropic material)

  double area_m2() const;           ///< A
  double second_moment_m4() const;  ///< I = pi (D^4 - d^4) / 64, about either axis of the section
  double polar_moment_m4() const;   ///< J = 2 I (circular sections warp nothing)
  /// Timoshenko's shear coefficient of a solid circle, 6 (1 + nu) / (7 + 6 nu), with nu from E and G; the
  /// thin-walled tube's 2 (1 + nu) / (4 + 3 nu) for an annulus (Cowper 1966 gives both; the rod's shear
  /// compliance is 10^-4 to 10^-6 of its bending compliance for an instrument, so the choice barely shows).
  double shear_coefficient() const;
};

/// The rod's stiffness matrices in the material frame (d1, d2 across the section, d3 along the axis): bending
/// and twisting (EI, EI, GJ; N m^2) and shearing and stretching (k G A, k G A, E A; N).
struct RodStiffness {
  Vec3 bend_twist_n_m2 = Vec3::Zero();
  Vec3 shear_stretch_n = Vec3::Zero();
};

/// The stiffness of `section`; throws InputError for a section that is not a solid circle or an annulus or a
/// material that is not positive.
RodStiffness rod_stiffness(const RodSection& section);

}  // namespace vascsim::rod
