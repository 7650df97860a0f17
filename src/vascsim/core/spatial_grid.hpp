#pragma once
// Uniform-grid spatial index for fixed point sets (rest positions): radius queries and nearest
// neighbour distances in O(1) expected time per point. Built once at initialisation.

#include <functional>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

class SpatialGrid {
 public:
  /// Indexes `points` (#N, m) in cubic cells of edge `cell_size` (m, > 0). The points are copied.
  SpatialGrid(const Vec3Array& points, double cell_size);

  /// Calls visit(j, distance) for every indexed point j with |points[j] - p| < radius.
  void for_each_within(const Vec3& p, double radius, const std::function<void(Index, double)>& visit) const;

  /// Distance from point i to its nearest other indexed point (m); +inf if there is none within
  /// `max_search` (m).
  double nearest_distance(Index i, double max_search) const;

  double cell_size() const { return cell_; }

 private:
  Eigen::Vector3i cell_of(const Vec3& p) const;
  Vec3Array points_;
  Vec3 origin_;
  double cell_;
  Eigen::Vector3i dims_;
  std::vector<Index> cell_start_;  // CSR over cells (size = cells + 1)
  std::vector<Index> cell_items_;
};

/// Mean nearest-neighbour spacing (the Delta-bar of docs/model/03-neighbourhoods.md), m. Requires >= 2
/// points.
double mean_nearest_spacing(const Vec3Array& points);

/// Smallest nearest-neighbour spacing, m.
double min_nearest_spacing(const Vec3Array& points);

}  // namespace vascsim
