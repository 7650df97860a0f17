#include "vascsim/render/tool_geometry.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace vascsim::render {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// Two unit vectors completing `axis` to a right-handed orthonormal basis (e1 x e2 = axis).
void basis(const Float3& axis, Float3& e1, Float3& e2) {
  const Float3 helper = std::abs(axis.x()) < 0.9f ? Float3::UnitX() : Float3::UnitY();
  e1 = axis.cross(helper).normalized();
  e2 = axis.cross(e1);
}

std::uint32_t add_vertex(SolidMesh& m, const Float3& p, const Float3& n) {
  m.positions_m.push_back(p);
  m.normals.push_back(n);
  return static_cast<std::uint32_t>(m.positions_m.size() - 1);
}

// A ring of `segments` vertices at `centre` with radius r in the plane normal to the axis; normals given
// by normal(angle direction).
template <typename NormalFn>
std::uint32_t add_ring(SolidMesh& m, const Float3& centre, float r, const Float3& e1, const Float3& e2,
                       int segments, NormalFn normal) {
  const auto first = static_cast<std::uint32_t>(m.positions_m.size());
  for (int k = 0; k < segments; ++k) {
    const float a = kTwoPi * static_cast<float>(k) / static_cast<float>(segments);
    const Float3 radial = std::cos(a) * e1 + std::sin(a) * e2;
    add_vertex(m, centre + r * radial, normal(radial));
  }
  return first;
}

// Quads between ring a and ring b (b further along the axis); outward for rings around the axis.
void connect(SolidMesh& m, std::uint32_t a, std::uint32_t b, int segments) {
  for (int k = 0; k < segments; ++k) {
    const std::uint32_t k1 = static_cast<std::uint32_t>((k + 1) % segments),
                        k0 = static_cast<std::uint32_t>(k);
    m.triangles.push_back({a + k0, a + k1, b + k1});
    m.triangles.push_back({a + k0, b + k1, b + k0});
  }
}

// A disc (fan) closing ring `ring`; facing +axis if `forward`, else -axis.
void cap(SolidMesh& m, std::uint32_t ring, const Float3& centre, const Float3& normal, int segments,
         bool forward) {
  const std::uint32_t c = add_vertex(m, centre, normal);
  for (int k = 0; k < segments; ++k) {
    const std::uint32_t k1 = ring + static_cast<std::uint32_t>((k + 1) % segments),
                        k0 = ring + static_cast<std::uint32_t>(k);
    if (forward)
      m.triangles.push_back({c, k0, k1});
    else
      m.triangles.push_back({c, k1, k0});
  }
}

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

// A flat disc closing an end at `centre`, facing `outward`, with vertices of its own (normal along the axis).
void end_disc(SolidMesh& m, const Float3& centre, float r, const Float3& e1, const Float3& e2, int segments,
              const Float3& axis, const Float3& outward) {
  const std::uint32_t ring = add_ring(m, centre, r, e1, e2, segments, [&](const Float3&) { return outward; });
  cap(m, ring, centre, outward, segments, outward.dot(axis) > 0.0f);
}

}  // namespace

void SolidMesh::clear() {
  positions_m.clear();
  normals.clear();
  triangles.clear();
}

void append_capsule(SolidMesh& m, const ToolCapsule& tool, int segments) {
  segments = std::max(segments, 3);
  const Float3 d = tool.tip_m - tool.back_m;
  const float length = d.norm();
  const Float3 axis = length > 0.0f ? Float3(d / length) : Float3::UnitZ();
  Float3 e1, e2;
  basis(axis, e1, e2);
  const float r = tool.radius_m;
  const float cyl = tool.rounded_tip ? std::max(length - r, 0.0f) : length;
  const Float3 tip_centre = tool.back_m + cyl * axis;

  // Back disc (own vertices: flat normal), then the shaft with radial normals.
  const std::uint32_t back_flat =
      add_ring(m, tool.back_m, r, e1, e2, segments, [&](const Float3&) { return Float3(-axis); });
  cap(m, back_flat, tool.back_m, -axis, segments, false);
  const std::uint32_t back = add_ring(m, tool.back_m, r, e1, e2, segments, [](const Float3& n) { return n; });
  const std::uint32_t front = add_ring(m, tip_centre, r, e1, e2, segments, [](const Float3& n) { return n; });
  connect(m, back, front, segments);
  if (!tool.rounded_tip) {
    const std::uint32_t tip_flat =
        add_ring(m, tip_centre, r, e1, e2, segments, [&](const Float3&) { return axis; });
    cap(m, tip_flat, tip_centre, axis, segments, true);
    return;
  }
  // Hemisphere: rings at latitudes towards the apex, then a fan to the apex.
  const int stacks = std::max(segments / 4, 2);
  std::uint32_t previous = front;
  for (int s = 1; s < stacks; ++s) {
    const float phi = 0.5f * std::numbers::pi_v<float> * static_cast<float>(s) / static_cast<float>(stacks);
    const Float3 centre = tip_centre + r * std::sin(phi) * axis;
    const float ring_r = r * std::cos(phi);
    const std::uint32_t ring = add_ring(m, centre, ring_r, e1, e2, segments, [&](const Float3& radial) {
      return Float3(std::cos(phi) * radial + std::sin(phi) * axis);
    });
    connect(m, previous, ring, segments);
    previous = ring;
  }
  const std::uint32_t apex = add_vertex(m, tip_centre + r * axis, axis);
  for (int k = 0; k < segments; ++k) {
    const std::uint32_t k1 = previous + static_cast<std::uint32_t>((k + 1) % segments),
                        k0 = previous + static_cast<std::uint32_t>(k);
    m.triangles.push_back({k0, k1, apex});
  }
}

void append_tube(SolidMesh& m, const InstrumentTube& tube, int sides) {
  sides = std::max(sides, 3);
  const std::vector<Float3> p = distinct_points(tube);
  if (p.size() < 2) return;
  const std::vector<Float3> tangent = ring_tangents(p);
  const float r = tube.radius_m;
  Float3 e1, e2;
  basis(tangent.front(), e1, e2);
  end_disc(m, p.front(), r, e1, e2, sides, tangent.front(), -tangent.front());
  std::uint32_t previous = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (i > 0) {
      // Parallel transport: the smallest rotation from the last tangent to this one, then re-orthogonalised
      // against rounding.
      e1 = Eigen::Quaternionf::FromTwoVectors(tangent[i - 1], tangent[i]) * e1;
      e1 = (e1 - e1.dot(tangent[i]) * tangent[i]).normalized();
      e2 = tangent[i].cross(e1);
    }
    const std::uint32_t ring = add_ring(m, p[i], r, e1, e2, sides, [](const Float3& d) { return d; });
    if (i > 0) connect(m, previous, ring, sides);
    previous = ring;
  }
  end_disc(m, p.back(), r, e1, e2, sides, tangent.back(), tangent.back());
}

void append_arrow(SolidMesh& m, const Float3& origin, const Float3& vec, float radius, int segments) {
  segments = std::max(segments, 3);
  const float length = vec.norm();
  if (!(length > 0.0f) || !(radius > 0.0f)) return;
  const Float3 axis = vec / length;
  Float3 e1, e2;
  basis(axis, e1, e2);
  const float head_r = 2.5f * radius;
  const float head_len = std::min(0.25f * length, 8.0f * radius);
  const Float3 neck = origin + (length - head_len) * axis;
  const std::uint32_t tail_flat =
      add_ring(m, origin, radius, e1, e2, segments, [&](const Float3&) { return Float3(-axis); });
  cap(m, tail_flat, origin, -axis, segments, false);
  const std::uint32_t a = add_ring(m, origin, radius, e1, e2, segments, [](const Float3& n) { return n; });
  const std::uint32_t b = add_ring(m, neck, radius, e1, e2, segments, [](const Float3& n) { return n; });
  connect(m, a, b, segments);
  const std::uint32_t base_flat =
      add_ring(m, neck, head_r, e1, e2, segments, [&](const Float3&) { return Float3(-axis); });
  cap(m, base_flat, neck, -axis, segments, false);
  // Cone side: normals tilted by the cone's half-angle.
  const float slope = head_r / head_len;
  const std::uint32_t base = add_ring(m, neck, head_r, e1, e2, segments, [&](const Float3& n) {
    return Float3((n + slope * axis).normalized());
  });
  const std::uint32_t apex = add_vertex(m, origin + vec, axis);
  for (int k = 0; k < segments; ++k) {
    const std::uint32_t k1 = base + static_cast<std::uint32_t>((k + 1) % segments),
                        k0 = base + static_cast<std::uint32_t>(k);
    m.triangles.push_back({k0, k1, apex});
  }
}

double signed_volume(const std::vector<Float3>& p,
                     const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  double v = 0.0;
  for (const auto& t : triangles)
    v += p[t[0]].cast<double>().dot(p[t[1]].cast<double>().cross(p[t[2]].cast<double>()));
  return v / 6.0;
}

}  // namespace vascsim::render
