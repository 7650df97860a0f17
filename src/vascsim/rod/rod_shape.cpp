#include "vascsim/rod/rod_shape.hpp"

#include <fmt/format.h>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

RodRestShape rod_from_polyline(const Vec3Array& nodes, const Vec3& normal) {
  if (nodes.size() < 2) throw InputError("rod: a rod needs at least two nodes");
  RodRestShape r;
  r.nodes = nodes;
  Vec3 t_prev = Vec3::Zero();
  for (std::size_t j = 0; j + 1 < nodes.size(); ++j) {
    const Vec3 e = nodes[j + 1] - nodes[j];
    if (!(e.norm() > 0.0) || !e.allFinite())
      throw InputError(fmt::format("rod: edge {} has no length (nodes {} and {} coincide)", j, j, j + 1));
    const Vec3 t = e.normalized();
    if (j == 0) {
      const Vec3 d1 = normal - normal.dot(t) * t;
      if (!(d1.norm() > 1e-9 * normal.norm()))
        throw InputError("rod: the section's normal runs along the first edge; give one across it");
      Mat3 R;
      R.col(0) = d1.normalized();
      R.col(2) = t;
      R.col(1) = t.cross(R.col(0));
      r.frames.push_back(Quaternion(R).normalized());
    } else {
      if (!(t.dot(t_prev) > -1.0 + 1e-9))
        throw InputError(fmt::format("rod: edge {} turns back on edge {}", j, j - 1));
      r.frames.push_back((Quaternion::FromTwoVectors(t_prev, t) * r.frames.back()).normalized());
    }
    t_prev = t;
  }
  return r;
}

RodRestShape straight_rod(const Vec3& base, const Vec3& axis, const Vec3& normal, double length_m,
                          int edges) {
  return shaped_tip_rod(base, axis, normal, length_m, edges, 0.0, 0.0);
}

RodRestShape shaped_tip_rod(const Vec3& base, const Vec3& axis, const Vec3& normal, double length_m,
                            int edges, double tip_radius_m, double tip_angle_rad) {
  if (edges < 1) throw InputError(fmt::format("rod: {} edges; a rod needs at least one", edges));
  if (!(length_m > 0.0) || !std::isfinite(length_m))
    throw InputError(fmt::format("rod: length {} m must be positive", length_m));
  if (!(axis.norm() > 0.0)) throw InputError("rod: the axis has no direction");
  const double arc = tip_angle_rad != 0.0 ? tip_radius_m * std::abs(tip_angle_rad) : 0.0;
  if (tip_angle_rad != 0.0 && (!(tip_radius_m > 0.0) || !(arc < length_m)))
    throw InputError(
        fmt::format("rod: a tip of radius {} m turning by {} rad is {} m long, not shorter than the "
                    "rod's {} m",
                    tip_radius_m, tip_angle_rad, arc, length_m));
  const Vec3 t = axis.normalized();
  const Vec3 n0 = normal - normal.dot(t) * t;
  if (!(n0.norm() > 1e-9 * normal.norm()))
    throw InputError("rod: the section's normal runs along the axis; give one across it");
  const Vec3 n = n0.normalized();
  const double shaft = length_m - arc;
  Vec3Array nodes;
  for (int k = 0; k <= edges; ++k) {
    const double s = length_m * k / edges;
    if (s <= shaft || arc == 0.0) {
      nodes.push_back(base + s * t);
    } else {
      // On the arc: angle phi = (s - shaft) / r turned towards n (its sign carries the direction).
      const double phi = (s - shaft) / tip_radius_m;
      const double sign = tip_angle_rad > 0.0 ? 1.0 : -1.0;
      nodes.push_back(base + shaft * t + tip_radius_m * std::sin(phi) * t +
                      sign * tip_radius_m * (1.0 - std::cos(phi)) * n);
    }
  }
  return rod_from_polyline(nodes, n);
}

}  // namespace vascsim::rod
