#pragma once
// Local material frame of a vessel wall at one node: the orthonormal triad (axial e_z, circumferential
// e_theta, radial e_r) in the reference configuration, right-handed as e_r x e_theta = e_z. Anisotropic
// hyperelastic laws (hgo_law.hpp) build their fibre directions from it; isotropic laws ignore it.
//
// The frame depends only on the geometry (centre line and wall), not on the law, so a model stores one
// MaterialFrame per node (9 doubles), computes it once at set-up, and passes a pointer to it with every
// law evaluation (see hyperelastic_law.hpp).

#include "vascsim/core/types.hpp"

namespace vascsim::materials {

struct MaterialFrame {
  Vec3 axial = Vec3::UnitZ();            ///< e_z, along the centre line
  Vec3 circumferential = Vec3::UnitY();  ///< e_theta = e_z x e_r
  Vec3 radial = Vec3::UnitX();           ///< e_r, outward wall normal
};

/// Orthonormal frame from an axial direction and a radial direction (neither need be unit; `radial` need
/// not be orthogonal to `axial`: its axial part is removed). e_theta = e_z x e_r.
/// Throws InputError if either vector is zero or not finite, or if they are (nearly) parallel.
MaterialFrame make_material_frame(const Vec3& axial, const Vec3& radial);

}  // namespace vascsim::materials
