#pragma once
// A capsule (a cylinder of radius r around the segment a-b with hemispherical ends) as a closed triangle
// surface, for writing the rigid tools (the catheter) into the VTK output next to the wall.

#include "vascsim/geometry/vessel_body.hpp"

namespace vascsim {

/// The capsule around segment a-b (m) of radius `radius_m` > 0 as a RenderSurface: `segments` (>= 3) around
/// the axis, a quarter as many latitude rings per hemisphere; outward normals, triangles counter-clockwise
/// seen from outside, every triangle flagged outer. a = b gives a sphere.
RenderSurface capsule_surface(const Vec3& a, const Vec3& b, double radius_m, int segments = 24);

/// Appends `part` to `whole` (several tools in one surface).
void append_surface(RenderSurface& whole, const RenderSurface& part);

}  // namespace vascsim
