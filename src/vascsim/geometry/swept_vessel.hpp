#pragma once
// Vessel wall swept along a centre-line: the make_tube lattice (radial layer, angle, axial) mapped by
// X = C(s) + r (cos(theta) N(s) + sin(theta) B(s)) with the rotation-minimising frame (T, N, B),
// plus a closed triangle surface of the wall for rendering.

#include <array>
#include <vector>

#include "vascsim/geometry/centerline.hpp"
#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

/// A graded lattice (geometry.refine, docs/scene-format.md): node_spacing_m inside a window of the wall and a
/// margin around it, coarsening by `growth` per step outside it up to the spec's own node_spacing_m. The
/// window's edges and the margin's are lattice lines, so a wall patch of the window's extent has its
/// outermost nodes on its edges.
struct WallRefinement {
  bool enabled = false;
  double angle_center_deg = 0.0, angle_half_width_deg = 0.0;  ///< around the centre-line, from N towards B
  double s_center_m = 0.0, s_half_length_m = 0.0;             ///< along it (arc length)
  double node_spacing_m = 0.0;  ///< the fine spacing (along the wall and through it)
  double margin_m = 0.0;  ///< fine beyond the window's edges (at the mid-wall radius around the centre-line)
  double growth = 1.2;    ///< ratio of successive steps outside, in (1, 3]
};

struct SweptVesselSpec {
  double outer_radius_m = 1.5e-3;
  double wall_thickness_m = 0.3e-3;
  double node_spacing_m = 0.15e-3;  ///< target spacing Delta along all three directions
  int min_layers =
      3;  ///< minimum node layers through the wall (docs/model/00-design-decisions.md, decision 2), >= 3
  /// A lattice line runs at this angle around the centre-line, deg (from N towards B); see TubeSpec.
  double lattice_angle_deg = 0.0;
  /// Lattice counts around and along the centre-line when > 0 (see TubeSpec); 0: from node_spacing_m.
  int angular_nodes = 0, axial_nodes = 0;
  WallRefinement
      refine;  ///< a graded lattice instead of a uniform one (counts and lattice angle then unused)
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
  /// Per column its angle (rad, and deg in [0, 360)), per cross-section its arc length (m): equally spaced
  /// unless the lattice is graded.
  std::vector<double> theta_rad, theta_deg, s_m;
  bool graded = false;
};

/// Throws InputError for a bad spec, a centre-line whose smallest radius of curvature is <= the outer
/// radius, more than 5e7 nodes, or a virtual tetrahedron that is not positive after the mapping
/// (the message names the tetrahedron and its lattice cell).
SweptVessel make_swept_vessel(const Centerline& centerline, const SweptVesselSpec& spec);

}  // namespace vascsim
