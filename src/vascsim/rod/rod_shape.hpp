#pragma once
// The rest shape of a rod (docs/model/26-rod.md): its nodes and the material frame of each edge. The frame's
// d3 runs along the edge; d1 and d2 span the section. A rod's natural curvature and twist are whatever its
// rest shape has: the rod's energy is zero there, so a shaped tip keeps its shape when nothing loads it.

#include <Eigen/Geometry>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim::rod {

using Quaternion = Eigen::Quaterniond;

struct RodRestShape {
  Vec3Array nodes;                 ///< N + 1 nodes, m
  std::vector<Quaternion> frames;  ///< N edge frames (unit): column k of the rotation is d_(k+1)
};

/// Frames for the polyline `nodes` by parallel transport: the first edge's d1 is `normal` made perpendicular
/// to that edge, each next frame is the last one turned by the smallest rotation that takes its edge onto the
/// next (no twist). Throws InputError for fewer than two nodes, a zero-length edge, a normal along the first
/// edge or an edge that turns back on the last one.
RodRestShape rod_from_polyline(const Vec3Array& nodes, const Vec3& normal);

/// A straight rod of `length_m` from `base` along `axis` in `edges` equal edges, d1 along `normal`.
RodRestShape straight_rod(const Vec3& base, const Vec3& axis, const Vec3& normal, double length_m, int edges);

/// A rod whose distal end is shaped (an angled or J tip): straight from `base` along `axis`, then an arc of
/// radius `tip_radius_m` turning by `tip_angle_rad` towards `normal` (the frame's d1), the whole of arc
/// length `length_m` in `edges` edges of equal arc length (the arc's edges are its chords). An angle of 0 is
/// a straight rod.
RodRestShape shaped_tip_rod(const Vec3& base, const Vec3& axis, const Vec3& normal, double length_m,
                            int edges, double tip_radius_m, double tip_angle_rad);

}  // namespace vascsim::rod
