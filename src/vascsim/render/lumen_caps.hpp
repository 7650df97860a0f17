#pragma once
// The lumen as a closed surface for the fluoroscopy pass: the inner-wall triangles of a RenderFrame plus
// fan caps over every open end (boundary loop) of that inner wall. The caps use only existing vertices
// (a fan from the loop's first vertex), so they follow the deformation without any update. A fan over a
// non-convex loop overlaps itself, but with consistent orientation the overlaps cancel in the signed
// path length the fluoroscopy pass sums, which only depends on the boundary of the surface.

#include <array>
#include <cstdint>
#include <vector>

namespace vascsim::render {

/// The triangles whose three vertices are inner (outer[i] == 0), then the caps, oriented like the inner
/// wall (towards the lumen axis: inward for the lumen solid). Empty if `outer` is empty or no triangle is
/// inner.
std::vector<std::array<std::uint32_t, 3>> lumen_surface(
    const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<std::uint8_t>& outer);

}  // namespace vascsim::render
