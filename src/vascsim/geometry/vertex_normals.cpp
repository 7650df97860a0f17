#include "vascsim/geometry/vertex_normals.hpp"

#include <fmt/format.h>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim {

void vertex_normals(const std::vector<std::array<Index, 3>>& triangles, const Vec3Array& positions_m,
                    Vec3Array& normals) {
  const auto nv = static_cast<Index>(positions_m.size());
  normals.assign(positions_m.size(), Vec3::Zero());
  for (const auto& t : triangles) {
    for (Index k : t)
      if (k < 0 || k >= nv)
        throw InputError(fmt::format("vertex normals: triangle vertex {} out of range", k));
    const Vec3& a = positions_m[static_cast<std::size_t>(t[0])];
    const Vec3 c = (positions_m[static_cast<std::size_t>(t[1])] - a)
                       .cross(positions_m[static_cast<std::size_t>(t[2])] - a);
    const double len = c.norm();
    if (!(len > 0.0)) continue;  // degenerate: no direction to contribute
    const Vec3 unit = c / len;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = positions_m[static_cast<std::size_t>(t[k])];
      const Vec3 u = positions_m[static_cast<std::size_t>(t[(k + 1) % 3])] - p;
      const Vec3 w = positions_m[static_cast<std::size_t>(t[(k + 2) % 3])] - p;
      normals[static_cast<std::size_t>(t[k])] += std::atan2(u.cross(w).norm(), u.dot(w)) * unit;
    }
  }
  for (Vec3& n : normals) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
}

}  // namespace vascsim
