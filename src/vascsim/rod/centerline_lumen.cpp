#include "vascsim/rod/centerline_lumen.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

CenterlineLumen::CenterlineLumen(Centerline centerline, double radius_m)
    : c_(std::move(centerline)), radius_m_(radius_m) {
  if (!(radius_m > 0.0) || !std::isfinite(radius_m))
    throw InputError(fmt::format("rod contact: the lumen's radius {} m must be positive", radius_m));
  double h = 0.02 * radius_m;
  if (c_.min_radius_of_curvature() > 0.0 && std::isfinite(c_.min_radius_of_curvature()))
    h = std::min(h, 0.02 * c_.min_radius_of_curvature());
  const int n = std::max(1, static_cast<int>(std::ceil(c_.length() / h)));
  for (int k = 0; k <= n; ++k) {
    const double s = c_.length() * k / n;
    points_.push_back(c_.position(s));
  }
  grid_ = std::make_unique<SpatialGrid>(points_, radius_m);
}

LumenPoint CenterlineLumen::at(const Vec3& x) const {
  // The nearest sample (within one and a half radii through the grid; a point farther out scans them all).
  Index best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  grid_->for_each_within(x, 1.5 * radius_m_, [&](Index k, double d) {
    if (d < best_d) best_d = d, best = k;
  });
  if (best < 0)
    for (std::size_t k = 0; k < points_.size(); ++k)
      if (const double d = (x - points_[k]).norm(); d < best_d) best_d = d, best = static_cast<Index>(k);
  // The nearer of the chords beside it; the first and the last continued past the ends.
  const Index last = static_cast<Index>(points_.size()) - 1;
  Vec3 centre = points_[static_cast<std::size_t>(best)];
  Vec3 axis = Vec3::UnitZ();  // the nearer chord's direction (there is always one: two samples at least)
  double nearest = std::numeric_limits<double>::infinity();
  for (Index a = std::max<Index>(0, best - 1); a < std::min(best + 1, last); ++a) {
    const Vec3& p = points_[static_cast<std::size_t>(a)];
    const Vec3& q = points_[static_cast<std::size_t>(a) + 1];
    double t = (x - p).dot(q - p) / (q - p).squaredNorm();
    t = std::clamp(t, a == 0 ? -std::numeric_limits<double>::infinity() : 0.0,
                   a + 1 == last ? std::numeric_limits<double>::infinity() : 1.0);
    const Vec3 c = p + t * (q - p);
    if (const double d = (x - c).norm(); d < nearest) {
      nearest = d;
      centre = c;
      axis = (q - p).normalized();
    }
  }
  LumenPoint p;
  p.axis = axis;
  p.radius_m = radius_m_;
  // The distance to the sampled polyline, so that the outward direction is exactly its gradient (the rod's
  // line search needs its energy and gradient consistent).
  const Vec3 v = x - centre;
  p.distance_m = v.norm();
  if (p.distance_m > 0.0) {
    p.outward = v / p.distance_m;
  } else {
    const Vec3 any = std::abs(p.axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    p.outward = (any - any.dot(p.axis) * p.axis).normalized();
  }
  return p;
}

}  // namespace vascsim::rod
