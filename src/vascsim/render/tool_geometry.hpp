#pragma once
// Triangle meshes of what is drawn besides the wall, built on the CPU every frame (a few hundred to a few
// thousand triangles): a tool capsule (shaft + hemispherical tip) and a flexible instrument's tube (a circle
// swept along its centre-line), both closed and outward-oriented so the fluoroscopy pass can measure the
// path length through them, and the force arrow (shaft + cone).

#include <array>
#include <cstdint>
#include <vector>

#include "vascsim/render/render_frame.hpp"

namespace vascsim::render {

struct SolidMesh {
  std::vector<Float3> positions_m;
  std::vector<Float3> normals;
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise seen from outside
  void clear();
};

/// Appends a closed capsule: a flat disc at back_m, a cylinder, and a hemisphere whose apex is tip_m (a
/// flat disc there instead if !rounded_tip). `segments` around the axis (>= 3).
void append_capsule(SolidMesh& mesh, const ToolCapsule& tool, int segments = 32);

/// Appends the closed tube of `tube` (a 120-node wire with 12 sides: under 3000 triangles): a ring of
/// `sides` (>= 3) vertices round every centre-line point, in the plane across the mean of the directions of
/// its two segments, with radial normals; a flat disc (own vertices, normal along the axis) at each end. Each
/// ring's first vertex is carried from the previous ring by the smallest rotation between their tangents, so
/// the tube does not twist and its quads do not shear round a bend. Points closer than a thousandth of the
/// radius to the previous kept point are dropped; fewer than two points left: nothing is appended.
void append_tube(SolidMesh& mesh, const InstrumentTube& tube, int sides = 12);

/// Appends an arrow from `origin_m` along `vector_m` (its full length): a shaft of radius `radius_m`
/// and a cone head 2.5 radii wide and a quarter of the length (at most 8 radii) long.
void append_arrow(SolidMesh& mesh, const Float3& origin_m, const Float3& vector_m, float radius_m,
                  int segments = 20);

/// Signed enclosed volume (divergence theorem), m^3: positive for a closed outward-oriented mesh.
double signed_volume(const std::vector<Float3>& positions,
                     const std::vector<std::array<std::uint32_t, 3>>& triangles);

}  // namespace vascsim::render
