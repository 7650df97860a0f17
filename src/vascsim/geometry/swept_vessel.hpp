#pragma once
// Vessel wall swept along a centre-line: the make_tube lattice (radial layer, angle, axial) mapped by
// X = C(s) + r (cos(theta) N(s) + sin(theta) B(s)) with the rotation-minimising frame (T, N, B),
// plus a closed triangle surface of the wall for rendering.

#include <array>
#include <vector>

#include "vascsim/geometry/centerline.hpp"
#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

struct SweptVesselSpec {
  double outer_radius_m = 1.5e-3;
  double wall_thickness_m = 0.3e-3;
  double node_spacing_m = 0.15e-3;  ///< target spacing Delta along all three directions
  int min_layers = 3;               ///< minimum node layers through the wall (docs/model.md design decision 2), >= 3
  /// A lattice line runs at this angle around the centre-line, deg (from N towards B); see TubeSpec.
  double lattice_angle_deg = 0.0;
  /// Lattice counts around and along the centre-line when > 0 (see TubeSpec); 0: from node_spacing_m.
  int angular_nodes = 0, axial_nodes = 0;
};

struct SweptVessel {
  /// kind "swept_vessel"; node (ir, it, iz) has index ir + nr (it + nt iz) as in make_tube. `tube` is
  /// left empty (it describes a z-aligned straight cylinder only).
  NodeCloud cloud;
  /// Outward-oriented triangles over surface_vertices: outer wall, inner wall (normal into the lumen),
  /// end rings at s = 0 and s = length. Watertight by index: every edge is shared by two triangles.
  std::vector<std::array<Index, 3>> triangles;
  /// nt x nz outer-wall vertices (index it + nt iz), then nt x nz inner-wall vertices; they coincide
  /// with the outer and inner node layers.
  Vec3Array surface_vertices;
  /// Smooth wall normals (radial outward on the outer wall, towards the axis on the inner wall); the
  /// rim vertices shared with the end rings keep the wall normal.
  Vec3Array normals;
  /// u = s / length along the centre-line, v = theta / (2 pi) in [0, 1). The seam is shared (not
  /// split), so a renderer that needs v = 1 on the last column must duplicate the seam vertices.
  std::vector<Eigen::Vector2d> uv;
  double length_m = 0.0;  ///< centre-line arc length
  int radial_layers = 0, angular_nodes = 0, axial_nodes = 0;
  /// Angle of lattice column 0, rad (lattice_phase_rad of the spec's lattice angle); column k is at
  /// angle_phase_rad + 2 pi k / angular_nodes.
  double angle_phase_rad = 0.0;
};

/// Throws InputError for a bad spec, a centre-line whose smallest radius of curvature is <= the outer
/// radius, more than 5e7 nodes, or a virtual tetrahedron that is not positive after the mapping
/// (the message names the tetrahedron and its lattice cell).
SweptVessel make_swept_vessel(const Centerline& centerline, const SweptVesselSpec& spec);

}  // namespace vascsim
