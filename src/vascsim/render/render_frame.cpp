#include "vascsim/render/render_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "vascsim/core/error.hpp"

namespace vascsim::render {

Float3 arrow_vector_m(const ForceArrow& arrow, const Bounds& scene) {
  const float threshold = std::max(arrow.threshold_n, 1e-9f);
  const float per_newton = arrow.length_per_newton_m > 0.0f
                               ? arrow.length_per_newton_m
                               : 0.3f * static_cast<float>(scene.radius()) / threshold;
  return arrow.force_n * per_newton;
}

Bounds frame_bounds(const RenderFrame& frame) {
  Bounds b = scene_bounds(frame);
  if (frame.force) {
    const Vec3 head = (frame.force->origin_m + arrow_vector_m(*frame.force, b)).cast<double>();
    b.min = b.min.cwiseMin(head);
    b.max = b.max.cwiseMax(head);
  }
  return b;
}

Bounds scene_bounds(const RenderFrame& frame) {
  Eigen::Vector3d lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Float3& p : frame.positions_m) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  for (const ToolCapsule& t : frame.tools) {
    const Vec3 r = Vec3::Constant(t.radius_m);
    for (const Float3& p : {t.back_m, t.tip_m}) {
      lo = lo.cwiseMin(p.cast<double>() - r);
      hi = hi.cwiseMax(p.cast<double>() + r);
    }
  }
  for (const InstrumentTube& tube : frame.instruments) {
    const Vec3 r = Vec3::Constant(tube.radius_m);
    for (const Float3& p : tube.centreline_m) {
      lo = lo.cwiseMin(p.cast<double>() - r);
      hi = hi.cwiseMax(p.cast<double>() + r);
    }
  }
  Bounds b;
  if (lo.allFinite() && hi.allFinite()) {
    b.min = lo;
    b.max = hi;
  }
  return b;
}

void compute_normals(const std::vector<Float3>& positions,
                     const std::vector<std::array<std::uint32_t, 3>>& triangles,
                     std::vector<Float3>& normals) {
  normals.assign(positions.size(), Float3::Zero());
  for (const auto& t : triangles) {
    // The cross product's length is twice the area: area weighting for free.
    const Float3 n = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    for (std::uint32_t i : t) normals[i] += n;
  }
  for (Float3& n : normals) {
    const float len = n.norm();
    n = len > 0.0f ? Float3(n / len) : Float3::UnitZ();
  }
}

std::vector<std::array<std::uint32_t, 2>> tet_edge_list(const std::vector<Tet>& tets) {
  std::vector<std::array<std::uint32_t, 2>> edges;
  edges.reserve(6 * tets.size());
  for (const Tet& t : tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const auto i = static_cast<std::uint32_t>(t[a]), j = static_cast<std::uint32_t>(t[b]);
        edges.push_back({std::min(i, j), std::max(i, j)});
      }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

void validate_frame(const RenderFrame& frame) {
  const std::size_t nv = frame.positions_m.size();
  auto size_check = [nv](std::size_t size, const char* name, bool optional) {
    if (size != nv && !(optional && size == 0))
      throw InputError(
          fmt::format("render frame: {} has {} entries for {} surface vertices", name, size, nv));
  };
  size_check(frame.normals.size(), "normals", true);
  size_check(frame.uv.size(), "uv", true);
  size_check(frame.outer.size(), "outer", true);
  if (frame.scalar) size_check(frame.scalar->values.size(), "scalar values", false);
  for (std::size_t i = 0; i < nv; ++i)
    if (!frame.positions_m[i].allFinite())
      throw InputError(fmt::format("render frame: surface vertex {} is not finite", i));
  for (std::size_t f = 0; f < frame.triangles.size(); ++f)
    for (std::uint32_t i : frame.triangles[f])
      if (i >= nv) throw InputError(fmt::format("render frame: triangle {} uses vertex {} of {}", f, i, nv));
  const std::size_t nn = frame.node_points_m.size();
  for (std::size_t e = 0; e < frame.tet_edges.size(); ++e)
    for (std::uint32_t i : frame.tet_edges[e])
      if (i >= nn) throw InputError(fmt::format("render frame: tet edge {} uses node {} of {}", e, i, nn));
  for (std::size_t k = 0; k < frame.tools.size(); ++k) {
    const ToolCapsule& t = frame.tools[k];
    if (!t.back_m.allFinite() || !t.tip_m.allFinite() || !(t.radius_m > 0.0f) || !std::isfinite(t.radius_m))
      throw InputError(fmt::format("render frame: tool {} has a non-finite end or a radius <= 0", k));
  }
  for (std::size_t k = 0; k < frame.instruments.size(); ++k) {
    const InstrumentTube& tube = frame.instruments[k];
    if (!(tube.radius_m > 0.0f) || !std::isfinite(tube.radius_m))
      throw InputError(fmt::format("render frame: instrument {} has a radius <= 0", k));
    for (std::size_t i = 0; i < tube.centreline_m.size(); ++i)
      if (!tube.centreline_m[i].allFinite())
        throw InputError(fmt::format("render frame: instrument {} point {} is not finite", k, i));
  }
  if (frame.force && (!frame.force->origin_m.allFinite() || !frame.force->force_n.allFinite()))
    throw InputError("render frame: the force arrow is not finite");
}

void assign_positions(RenderFrame& frame, const Vec3Array& positions_m) {
  frame.positions_m.resize(positions_m.size());
  for (std::size_t i = 0; i < positions_m.size(); ++i) frame.positions_m[i] = positions_m[i].cast<float>();
}

void assign_normals(RenderFrame& frame, const Vec3Array& normals) {
  frame.normals.resize(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) frame.normals[i] = normals[i].cast<float>();
}

}  // namespace vascsim::render
