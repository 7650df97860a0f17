#pragma once
// A rigid lumen of constant radius round a vessel's centre-line (geometry/centerline.hpp): the inside of the
// bundled vessels' walls for the rod's contact (lumen_contact.hpp). Beyond the centre-line's ends the lumen
// goes on straight along the end's tangent (the rod may reach past the modelled vessel).
//
// Queried at every node in every evaluation of the rod's energy, so the centre-line is sampled once, densely
// (at most a fiftieth of the lumen's radius and of the smallest radius of curvature apart: the chords'
// sagitta is below 10^-5 of the radius), and a query finds its nearest sample in a grid and projects onto the
// two chords beside it. The centre-line's own closest-point search (a scan of its arc-length samples and a
// golden-section refinement) took 90 % of a rod's solve.

#include <memory>

#include "vascsim/core/spatial_grid.hpp"
#include "vascsim/geometry/centerline.hpp"
#include "vascsim/rod/lumen_contact.hpp"

namespace vascsim::rod {

class CenterlineLumen final : public Lumen {
 public:
  /// Throws InputError for a radius that is not positive.
  CenterlineLumen(Centerline centerline, double radius_m);
  LumenPoint at(const Vec3& x) const override;
  const Centerline& centerline() const { return c_; }

 private:
  Centerline c_;
  double radius_m_ = 0.0;
  Vec3Array points_;  // the dense samples
  std::unique_ptr<SpatialGrid> grid_;
};

}  // namespace vascsim::rod
