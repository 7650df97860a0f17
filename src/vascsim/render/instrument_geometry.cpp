#include "vascsim/render/instrument_geometry.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vascsim::render {

namespace {

// The centre-line without repeated points: a zero-length segment has no direction.
std::vector<Float3> distinct_points(const InstrumentTube& tube) {
  std::vector<Float3> points;
  const float min_step = 1e-3f * tube.radius_m;
  for (const Float3& p : tube.centreline_m)
    if (points.empty() || (p - points.back()).norm() > min_step) points.push_back(p);
  return points;
}

// The axis of each ring: the segment's direction at the ends, the mean of the two segments' between (the
// previous segment's where the line turns back on itself and the mean vanishes).
std::vector<Float3> ring_tangents(const std::vector<Float3>& p) {
  const std::size_t n = p.size();
  std::vector<Float3> segment(n - 1);
  for (std::size_t j = 0; j + 1 < n; ++j) segment[j] = (p[j + 1] - p[j]).normalized();
  std::vector<Float3> tangent(n);
  tangent.front() = segment.front();
  tangent.back() = segment.back();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Float3 mean = segment[i - 1] + segment[i];
    tangent[i] = mean.norm() > 1e-4f ? Float3(mean.normalized()) : segment[i - 1];
  }
  return tangent;
}

// A unit vector across `axis`.
Float3 any_perpendicular(const Float3& axis) {
  const Float3 helper = std::abs(axis.x()) < 0.9f ? Float3::UnitX() : Float3::UnitY();
  return axis.cross(helper).normalized();
}

std::uint32_t add_tube_vertex(SolidMesh& m, const Float3& p, const Float3& n) {
  m.positions_m.push_back(p);
  m.normals.push_back(n);
  return static_cast<std::uint32_t>(m.positions_m.size() - 1);
}

// A flat disc closing the end at `centre`, facing `outward` (the ring runs counter-clockwise about
// `ring_axis`, so the fan's winding follows whether the disc faces along it or against it).
void add_end_disc(SolidMesh& m, const Float3& centre, const Float3& ring_axis,
                  const std::vector<Float3>& radial, float r, const Float3& outward) {
  const auto sides = static_cast<std::uint32_t>(radial.size());
  const std::uint32_t first = static_cast<std::uint32_t>(m.positions_m.size());
  for (const Float3& d : radial) add_tube_vertex(m, centre + r * d, outward);
  const std::uint32_t c = add_tube_vertex(m, centre, outward);
  const bool along = outward.dot(ring_axis) > 0.0f;
  for (std::uint32_t k = 0; k < sides; ++k) {
    const std::uint32_t k0 = first + k, k1 = first + (k + 1) % sides;
    if (along)
      m.triangles.push_back({c, k0, k1});
    else
      m.triangles.push_back({c, k1, k0});
  }
}

}  // namespace

void append_tube(SolidMesh& m, const InstrumentTube& tube, int sides) {
  sides = std::max(sides, 3);
  const std::vector<Float3> p = distinct_points(tube);
  if (p.size() < 2) return;
  const std::vector<Float3> tangent = ring_tangents(p);
  const float r = tube.radius_m;
  const auto n_sides = static_cast<std::uint32_t>(sides);

  // The unit radial directions of ring i's vertices, e1 and e2 = t x e1 spanning its plane (e1 x e2 = t).
  std::vector<Float3> radial(n_sides);
  Float3 e1 = any_perpendicular(tangent.front());
  auto ring_directions = [&](const Float3& t) {
    const Float3 e2 = t.cross(e1);
    for (std::uint32_t k = 0; k < n_sides; ++k) {
      const float a = 2.0f * std::numbers::pi_v<float> * static_cast<float>(k) / static_cast<float>(sides);
      radial[k] = std::cos(a) * e1 + std::sin(a) * e2;
    }
  };

  ring_directions(tangent.front());
  add_end_disc(m, p.front(), tangent.front(), radial, r, -tangent.front());
  std::uint32_t previous = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (i > 0) {
      // Parallel transport: the smallest rotation from the last tangent to this one, then re-orthogonalised
      // against rounding.
      e1 = Eigen::Quaternionf::FromTwoVectors(tangent[i - 1], tangent[i]) * e1;
      e1 = (e1 - e1.dot(tangent[i]) * tangent[i]).normalized();
      ring_directions(tangent[i]);
    }
    const auto ring = static_cast<std::uint32_t>(m.positions_m.size());
    for (const Float3& d : radial) add_tube_vertex(m, p[i] + r * d, d);
    if (i > 0)
      for (std::uint32_t k = 0; k < n_sides; ++k) {
        const std::uint32_t k0 = k, k1 = (k + 1) % n_sides;
        // Counter-clockwise seen from outside: the ring runs counter-clockwise about the axis.
        m.triangles.push_back({previous + k0, previous + k1, ring + k1});
        m.triangles.push_back({previous + k0, ring + k1, ring + k0});
      }
    previous = ring;
  }
  add_end_disc(m, p.back(), tangent.back(), radial, r, tangent.back());
}

}  // namespace vascsim::render
