#include "vascsim/model/materials/material_frame.hpp"

#include <fmt/format.h>

#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim::materials {

MaterialFrame make_material_frame(const Vec3& axial, const Vec3& radial) {
  const double na = axial.norm(), nr = radial.norm();
  if (!(na > 0.0) || !std::isfinite(na) || !(nr > 0.0) || !std::isfinite(nr))
    throw InputError(
        fmt::format("material frame: the axial ({}) and radial ({}) directions must be finite and "
                    "non-zero",
                    na, nr));
  MaterialFrame f;
  f.axial = axial / na;
  const Vec3 r = radial - radial.dot(f.axial) * f.axial;  // Gram-Schmidt
  // Relative tolerance: |sin(angle between axial and radial)| >= 1e-6.
  if (!(r.norm() > 1e-6 * nr))
    throw InputError("material frame: the radial direction is parallel to the axial direction");
  f.radial = r.normalized();
  f.circumferential = f.axial.cross(f.radial);
  return f;
}

}  // namespace vascsim::materials
