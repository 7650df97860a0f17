#include "vascsim/geometry/surface_samples.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

constexpr double kCreaseCos = 0.8660254037844386;  // cos 30 deg
constexpr double kShape = 0.5;                     // Phong tessellation's shape factor (see the header)

// Phong tessellation: the linear point p projected onto each vertex's tangent plane, the projections blended
// with the barycentric weights, and the result blended with p by the shape factor.
Vec3 lifted(const std::array<Vec3, 3>& P, const std::array<Vec3, 3>& N, const Vec3& w) {
  const Vec3 p = w[0] * P[0] + w[1] * P[1] + w[2] * P[2];
  Vec3 q = Vec3::Zero();
  for (int k = 0; k < 3; ++k) q += w[k] * (p - (p - P[k]).dot(N[k]) * N[k]);
  return (1.0 - kShape) * p + kShape * q;
}

}  // namespace

SurfaceSamples sample_surface(const RenderSurface& surface, double spacing_m, double own_edge_fraction) {
  if (!(spacing_m > 0.0) || !std::isfinite(spacing_m))
    throw InputError(
        fmt::format("surface samples: the spacing must be a positive length in metres (got {})", spacing_m));
  if (!(own_edge_fraction >= 0.0) || !std::isfinite(own_edge_fraction))
    throw InputError(fmt::format(
        "surface samples: the fraction of a triangle's own edge must be >= 0 (got {})", own_edge_fraction));
  const bool have_normals = surface.rest_normals.size() == surface.rest_vertices.size();
  std::vector<int> m_of(surface.triangles.size());
  double count = 0.0, finest = spacing_m;
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& tri = surface.triangles[t];
    const Vec3& a = surface.rest_vertices[tri[0]];
    const Vec3& b = surface.rest_vertices[tri[1]];
    const Vec3& c = surface.rest_vertices[tri[2]];
    const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
    const double longest = std::max({ab, bc, ca});
    double spacing = spacing_m;
    if (own_edge_fraction > 0.0 && ab + bc + ca > 0.0)
      spacing = std::min(spacing, own_edge_fraction * (ab + bc + ca) / 3.0);
    finest = std::min(finest, spacing);
    m_of[t] = std::max(1, static_cast<int>(std::ceil(longest / spacing - 1e-9)));
    count += static_cast<double>(m_of[t]) * m_of[t];
  }
  if (count > 2e7)
    throw InputError(fmt::format(
        "surface samples: {:.3g} samples at a spacing of {:.3g} m; use a larger spacing", count, spacing_m));
  SurfaceSamples out;
  out.spacing_min_m = finest;
  out.positions.reserve(static_cast<std::size_t>(count));
  out.normals.reserve(static_cast<std::size_t>(count));
  out.area_m2.reserve(static_cast<std::size_t>(count));
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& tri = surface.triangles[t];
    const std::array<Vec3, 3> P{surface.rest_vertices[tri[0]], surface.rest_vertices[tri[1]],
                                surface.rest_vertices[tri[2]]};
    const Vec3 cross = (P[1] - P[0]).cross(P[2] - P[0]);
    const double area = 0.5 * cross.norm();
    if (!(area > 0.0)) continue;  // a degenerate triangle stands for no surface
    const Vec3 face = cross.normalized();
    std::array<Vec3, 3> N{face, face, face};
    bool smooth = have_normals;
    if (have_normals)
      for (int k = 0; k < 3; ++k) {
        N[k] = surface.rest_normals[tri[k]];
        smooth = smooth && N[k].dot(face) >= kCreaseCos;
      }
    if (!smooth) N = {face, face, face};
    const int m = m_of[t];
    out.subdivisions_max = std::max(out.subdivisions_max, m);
    const double sub_area = area / (static_cast<double>(m) * m);
    // Sub-triangle centroids in barycentric coordinates: "up" triangles (i, j), (i+1, j), (i, j+1) and
    // "down" triangles (i+1, j), (i+1, j+1), (i, j+1), in units of 1/m.
    const auto add = [&](double i, double j) {
      const Vec3 w((m - i - j) / m, i / m, j / m);
      out.positions.push_back(smooth ? lifted(P, N, w) : Vec3(w[0] * P[0] + w[1] * P[1] + w[2] * P[2]));
      out.normals.push_back((w[0] * N[0] + w[1] * N[1] + w[2] * N[2]).normalized());
      out.area_m2.push_back(sub_area);
      out.triangle.push_back(static_cast<Index>(t));
      out.barycentric.push_back(w);
      out.smooth.push_back(smooth ? 1 : 0);
    };
    for (int i = 0; i < m; ++i)
      for (int j = 0; i + j < m; ++j) {
        add(i + 1.0 / 3.0, j + 1.0 / 3.0);
        if (i + j + 1 < m) add(i + 2.0 / 3.0, j + 2.0 / 3.0);
      }
  }
  return out;
}

}  // namespace vascsim
