#pragma once
// What a geometry block builds: the node cloud (the simulated body) plus, for vessels, the wall
// coordinates of every node (region selectors and "inward" directions use them) and the triangle
// surface rendered through the MLS map. One type for the three sources: centre-line sweeps (tube,
// vessel), imported meshes (mesh_wall) and plain lattices (box, beam).

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "vascsim/geometry/centerline.hpp"
#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

struct SweptVessel;
struct MeshWall;

/// Per-node position inside a vessel wall (rest configuration).
/// A node's cell along a graded wall (geometry.refine): half-way to its neighbouring columns and
/// cross-sections.
struct LatticeCell {
  double theta_lo_deg = 0.0,
         theta_hi_deg = 0.0;          ///< the cell's sides around the centre-line, from the node's angle
  double s_lo_m = 0.0, s_hi_m = 0.0;  ///< its ends along the centre-line (arc length)
};

struct WallCoordinates {
  double thickness_m = 0.0;
  /// Distance from the inner (lumen) surface into the wall along the wall normal, 0..thickness, m.
  std::vector<double> depth_m;
  /// Unit wall normal at the node, pointing away from the lumen.
  Vec3Array outward;
  /// Without surface_tag, a node with depth >= thickness - shell_tolerance is on the outer surface, one
  /// with depth <= shell_tolerance on the inner surface (m); lattices aligned with the wall use 1 % of
  /// the layer step.
  double shell_tolerance_m = 0.0;
  /// Spacing of the node layers through the wall, m (lattices aligned with the wall; 0: not layered).
  double layer_spacing_m = 0.0;

  // Centre-line coordinates: only for vessels swept along a centre-line (empty for imported meshes).
  std::shared_ptr<const Centerline> centerline;
  std::vector<double> s_m;        ///< arc length of the node's cross-section, m
  std::vector<double> theta_deg;  ///< angle around the centre-line from the frame's N towards B, [0, 360)
  double length_m = 0.0;          ///< centre-line length, m
  /// Lattice steps of a swept wall (0 for an imported mesh): the angle between node columns, deg, and the
  /// arc length between cross-sections, m. A node stands for the strip of half a step on either side.
  double angle_step_deg = 0.0;
  double s_step_m = 0.0;
  /// Per node, on a graded lattice only (empty on a uniform one, whose steps above are every node's): its
  /// cell. The steps above are then the finest.
  std::vector<LatticeCell> cells;

  /// Per node, when the generator knows it exactly (imported meshes: nodes snapped onto a surface):
  /// 1 on the inner (lumen) surface, 2 on the outer surface, 0 inside. Empty: decide by depth.
  std::vector<char> surface_tag;

  bool has_centerline() const { return centerline != nullptr; }
  bool on_outer(Index i) const {
    return surface_tag.empty() ? depth_m[i] >= thickness_m - shell_tolerance_m : surface_tag[i] == 2;
  }
  bool on_inner(Index i) const {
    return surface_tag.empty() ? depth_m[i] <= shell_tolerance_m : surface_tag[i] == 1;
  }
  /// Unit outward wall normal of the centre-line vessel at (s, theta) (rest).
  Vec3 radial(double s_m, double theta_deg) const;
};

/// A closed, outward-oriented triangle surface over rest vertices, rendered through the MLS map.
struct RenderSurface {
  std::vector<std::array<Index, 3>> triangles;
  Vec3Array rest_vertices;          ///< m
  Vec3Array rest_normals;           ///< unit, outward of the solid
  std::vector<Eigen::Vector2d> uv;  ///< texture coordinates (u along the centre-line, v around); may be empty
  std::vector<char> outer;          ///< per triangle: 1 on the outer wall (what a viewer draws), else 0
};

/// The render surface deformed to one state (the surface map's output).
struct SurfaceFrame {
  Vec3Array positions;      ///< m
  Vec3Array displacements;  ///< m
  Vec3Array normals;        ///< unit, recomputed from the deformed triangles
};

struct Body {
  NodeCloud cloud;
  std::optional<WallCoordinates> wall;
  std::optional<RenderSurface> surface;
};

/// A swept vessel with its centre-line: wall coordinates from the lattice indices, the swept surface
/// (outer wall triangles flagged outer).
Body body_from_swept_vessel(SweptVessel vessel, std::shared_ptr<const Centerline> centerline);

/// A make_tube cloud (cloud.tube set): wall coordinates from the cylinder (s = z, theta from +x towards
/// +y, as the straight centre-line's frame), the surface taken from `swept` (the same tube swept along
/// the straight centre-line: identical surface lattice for any number of wall layers).
Body body_from_tube(NodeCloud tube, SweptVessel swept);

/// A wall built from an imported mesh: wall depth, outward normal and the surface tags of the nodes
/// snapped onto the inner and outer surface; no centre-line.
Body body_from_mesh_wall(MeshWall wall);

/// A plain lattice (box, beam): no wall; the surface is the boundary of the virtual tetrahedra over the
/// nodes themselves (every face "outer").
Body body_from_lattice(NodeCloud cloud);

/// A wall swept along a centre-line: the nodes' mean distance from it, m. Requires body.wall with a
/// centre-line.
double mean_node_radius_m(const Body& body);

/// The lattice's node spacing along the wall, m: the square root of the wall area per column and
/// cross-section at the mean node radius, sqrt(r Delta_theta Delta_s), when the wall is swept along a
/// centre-line (the finest steps on a graded lattice); the generator's nominal spacing otherwise. A lattice
/// fitted to a patch (geometry.fit_lattice_to_patch) differs from the nominal spacing by up to a factor 1.5.
double along_wall_spacing_m(const Body& body);

}  // namespace vascsim
