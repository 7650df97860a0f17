#include "vascsim/geometry/capsule_surface.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vascsim {

namespace {

// Two unit vectors perpendicular to `axis` and to each other.
void perpendicular_basis(const Vec3& axis, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = axis.cross(helper).normalized();
  e2 = axis.cross(e1);
}

}  // namespace

RenderSurface capsule_surface(const Vec3& a, const Vec3& b, double radius_m, int segments) {
  segments = std::max(segments, 3);
  const Vec3 d = b - a;
  const double length = d.norm();
  const Vec3 axis = length > 0.0 ? Vec3(d / length) : Vec3::UnitZ();
  Vec3 e1, e2;
  perpendicular_basis(axis, e1, e2);
  const int stacks = std::max(segments / 4, 2);

  // Rings from the pole beyond a to the pole beyond b: latitude phi in (-pi/2, pi/2) on each hemisphere,
  // the a hemisphere centred at a, the b one at b (the cylinder joins their equators).
  RenderSurface s;
  auto add_vertex = [&](const Vec3& p, const Vec3& n) {
    s.rest_vertices.push_back(p);
    s.rest_normals.push_back(n);
  };
  add_vertex(a - radius_m * axis, -axis);
  std::vector<std::pair<Vec3, double>> rings;  // (centre of the sphere it lies on, latitude)
  for (int k = 1; k <= stacks; ++k)
    rings.emplace_back(a, -0.5 * std::numbers::pi * (1.0 - static_cast<double>(k) / stacks));
  for (int k = 0; k < stacks; ++k)
    rings.emplace_back(b, 0.5 * std::numbers::pi * static_cast<double>(k) / stacks);
  for (const auto& [centre, phi] : rings)
    for (int j = 0; j < segments; ++j) {
      const double t = 2.0 * std::numbers::pi * j / segments;
      const Vec3 radial = std::cos(t) * e1 + std::sin(t) * e2;
      const Vec3 n = std::cos(phi) * radial + std::sin(phi) * axis;
      add_vertex(centre + radius_m * n, n);
    }
  add_vertex(b + radius_m * axis, axis);

  const auto ring_start = [&](std::size_t r) {
    return static_cast<Index>(1 + r * static_cast<std::size_t>(segments));
  };
  const Index last = static_cast<Index>(s.rest_vertices.size() - 1);
  for (int j = 0; j < segments; ++j) {  // fan around the a pole
    const Index j1 = (j + 1) % segments;
    s.triangles.push_back({0, ring_start(0) + j1, ring_start(0) + j});
  }
  for (std::size_t r = 0; r + 1 < rings.size(); ++r)
    for (int j = 0; j < segments; ++j) {
      const Index j1 = (j + 1) % segments;
      const Index p0 = ring_start(r) + j, p1 = ring_start(r) + j1, q0 = ring_start(r + 1) + j,
                  q1 = ring_start(r + 1) + j1;
      s.triangles.push_back({p0, p1, q1});
      s.triangles.push_back({p0, q1, q0});
    }
  const Index top = ring_start(rings.size() - 1);
  for (int j = 0; j < segments; ++j) {  // fan around the b pole
    const Index j1 = (j + 1) % segments;
    s.triangles.push_back({top + j, top + j1, last});
  }
  s.outer.assign(s.triangles.size(), 1);
  return s;
}

void append_surface(RenderSurface& whole, const RenderSurface& part) {
  const auto offset = static_cast<Index>(whole.rest_vertices.size());
  whole.rest_vertices.insert(whole.rest_vertices.end(), part.rest_vertices.begin(), part.rest_vertices.end());
  whole.rest_normals.insert(whole.rest_normals.end(), part.rest_normals.begin(), part.rest_normals.end());
  for (const auto& t : part.triangles)
    whole.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  whole.outer.insert(whole.outer.end(), part.outer.begin(), part.outer.end());
}

}  // namespace vascsim
