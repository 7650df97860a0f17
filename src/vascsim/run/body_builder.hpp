#pragma once
// Building the body a scene's geometry block describes: the node cloud with its virtual tetrahedra, the
// wall coordinates of every node (vessels) and the render surface, whichever generator makes them (tube,
// centre-line sweep, imported mesh, box or beam lattice).

#include <vector>

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/model/materials/material_frame.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

/// Builds the body of a geometry block: node cloud, wall coordinates (vessels) and render surface. Throws
/// InputError for an unreadable or unusable mesh file.
Body build_body(const GeometrySpec& spec);

/// The node cloud of build_body.
NodeCloud build_geometry(const GeometrySpec& spec);

/// Per node, the wall frame (axial = centre-line tangent at the node's s, radial = outward wall normal) that
/// anisotropic laws take their fibres from. Throws InputError for a body without a centre-line.
std::vector<materials::MaterialFrame> wall_frames(const Body& body, const Scene& scene);

}  // namespace vascsim
