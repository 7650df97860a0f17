#pragma once
// The triangle mesh of a flexible instrument (InstrumentTube): a circle swept along the rod's centre-line.
// Closed and outward-oriented like the tool capsules, so the fluoroscopy pass measures the path length
// through it; built on the CPU every upload (a 120-node wire with 12 sides: under 3000 triangles).

#include "vascsim/render/render_frame.hpp"
#include "vascsim/render/tool_geometry.hpp"

namespace vascsim::render {

/// Appends the closed tube of `tube` to `mesh`: a ring of `sides` (>= 3) vertices round every centre-line
/// point, in the plane across the mean of the directions of its two segments, with radial normals; a flat
/// disc (own vertices, normal along the axis) at each end. Each ring's first vertex is carried from the
/// previous ring by the smallest rotation between their tangents, so the tube does not twist and its quads
/// do not shear round a bend. Points closer than a thousandth of the radius to the previous kept point are
/// dropped; fewer than two points left: nothing is appended.
void append_tube(SolidMesh& mesh, const InstrumentTube& tube, int sides = 12);

}  // namespace vascsim::render
