#include "vascsim/core/spatial_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {
constexpr double kMaxCells = 6.4e7;  // memory guard for the dense cell array

Eigen::AlignedBox3d bounds(const Vec3Array& pts) {
  Eigen::AlignedBox3d box;
  for (const auto& p : pts) box.extend(p);
  return box;
}
}  // namespace

SpatialGrid::SpatialGrid(const Vec3Array& points, double cell_size) : points_(points) {
  if (!(cell_size > 0.0) || !std::isfinite(cell_size))
    throw NumericalError("spatial grid: cell size must be > 0");
  for (const auto& p : points_)
    if (!p.allFinite()) throw InputError("spatial grid: a node position is not finite");
  const auto box = points_.empty() ? Eigen::AlignedBox3d(Vec3::Zero(), Vec3::Zero()) : bounds(points_);
  origin_ = box.min();
  const Vec3 extent = box.max() - box.min();
  cell_ = cell_size;
  // Coarsen the grid when a dense array over the bounding box would be too large.
  while ((extent / cell_ + Vec3::Ones()).prod() > kMaxCells) cell_ *= 2.0;
  for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::floor(extent[a] / cell_)) + 1;
  const std::size_t ncell = static_cast<std::size_t>(dims_.prod());
  std::vector<Index> count(ncell + 1, 0);
  std::vector<std::size_t> key(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3i c = cell_of(points_[i]);
    key[i] = static_cast<std::size_t>(c[0]) +
             static_cast<std::size_t>(dims_[0]) *
                 (static_cast<std::size_t>(c[1]) + static_cast<std::size_t>(dims_[1]) * c[2]);
    ++count[key[i] + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) count[c + 1] += count[c];
  cell_start_ = count;
  cell_items_.resize(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) cell_items_[count[key[i]]++] = static_cast<Index>(i);
}

Eigen::Vector3i SpatialGrid::cell_of(const Vec3& p) const {
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(static_cast<int>(std::floor((p[a] - origin_[a]) / cell_)), 0, dims_[a] - 1);
  return c;
}

void SpatialGrid::for_each_within(const Vec3& p, double radius,
                                  const std::function<void(Index, double)>& visit) const {
  const Eigen::Vector3i lo = cell_of(p - Vec3::Constant(radius));
  const Eigen::Vector3i hi = cell_of(p + Vec3::Constant(radius));
  const double r2 = radius * radius;
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const std::size_t c = static_cast<std::size_t>(x) +
                              static_cast<std::size_t>(dims_[0]) *
                                  (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_[1]) * z);
        for (Index k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          const Index j = cell_items_[k];
          const double d2 = (points_[j] - p).squaredNorm();
          if (d2 < r2) visit(j, std::sqrt(d2));
        }
      }
}

double SpatialGrid::nearest_distance(Index i, double max_search) const {
  double best = std::numeric_limits<double>::infinity();
  for (double r = cell_;; r *= 2.0) {
    const double radius = std::min(r, max_search);
    for_each_within(points_[i], radius, [&](Index j, double d) {
      if (j != i && d < best) best = d;
    });
    if (std::isfinite(best) || radius >= max_search) return best;
  }
}

namespace {
std::vector<double> nearest_spacings(const Vec3Array& points) {
  if (points.size() < 2) throw InputError("node cloud: at least 2 nodes are needed");
  const auto box = bounds(points);
  const double diag = std::max(box.diagonal().norm(), 1e-300);
  // A cell edge of about one mean spacing for a volume-filling cloud.
  const double cell = std::max(diag / std::cbrt(static_cast<double>(points.size())), diag * 1e-6);
  SpatialGrid grid(points, cell);
  std::vector<double> d(points.size());
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < points.size(); ++i)
    d[i] = grid.nearest_distance(static_cast<Index>(i), 2.0 * diag);
  return d;
}
}  // namespace

double mean_nearest_spacing(const Vec3Array& points) {
  const auto d = nearest_spacings(points);
  double s = 0.0;
  for (double x : d) s += x;
  return s / static_cast<double>(d.size());
}

double min_nearest_spacing(const Vec3Array& points) {
  const auto d = nearest_spacings(points);
  return *std::min_element(d.begin(), d.end());
}

}  // namespace vascsim
