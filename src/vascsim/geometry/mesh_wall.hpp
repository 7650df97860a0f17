#pragma once
// Vessel wall node cloud from a real surface mesh: an axis-aligned cubic lattice clipped to the wall
// solid (the shell of thickness t outside a lumen surface, or the solid between the inner and outer
// surfaces of a closed wall mesh), with the Kuhn virtual tetrahedra, plus a closed wall surface for
// rendering through the MLS map.

#include <array>
#include <string>
#include <vector>

#include "vascsim/geometry/node_cloud.hpp"
#include "vascsim/geometry/triangle_mesh.hpp"

namespace vascsim {

struct MeshWallSpec {
  /// "lumen": the mesh is the blood-side surface (closed, or open at the vessel ends) and the wall is
  /// the shell 0 <= signed distance <= wall_thickness_m outside it. "closed_wall": the mesh holds the
  /// inner and outer wall surfaces (>= 2 nested closed components) and the wall is the solid between.
  std::string kind = "lumen";
  double wall_thickness_m = 1.5e-3;  ///< t for kind "lumen", m (ignored for "closed_wall": measured)
  double node_spacing_m =
      0.5e-3;                   ///< requested lattice spacing, m; reduced to t / (min_layers + 0.5) if larger
  int min_layers = 3;           ///< minimum node layers through the thinnest wall (>= 2)
  std::string source = "mesh";  ///< name used in error messages (the file name)
};

struct MeshWall {
  /// kind "mesh_wall", spacing_m = lattice spacing Delta, box = bounding box of the nodes; tets are
  /// Kuhn tets of the lattice cubes, positively oriented.
  NodeCloud cloud;
  /// Per node: distance from the lumen (inner) surface into the wall, m. In [0, t] for "lumen"; for
  /// "closed_wall" it is the distance to the nearest inner surface (may exceed thickness_m where the
  /// wall is thicker than its thinnest point).
  std::vector<double> depth_m;
  /// Per node: unit wall normal pointing away from the lumen (towards the outer surface).
  Vec3Array outward;
  double thickness_m = 0.0;  ///< t: the given thickness ("lumen") or the thinnest measured ("closed_wall"), m
  int nominal_layers =
      0;  ///< floor(t / Delta) + 1 lattice planes fit across an axis-aligned wall of thickness t
  /// Closed wall surface, oriented outward of the wall solid: the inner surface (normals into the lumen)
  /// and the outer surface; for an open "lumen" mesh, rim strips join them at each opening.
  std::vector<std::array<Index, 3>> triangles;
  Vec3Array surface_vertices;          ///< m
  Vec3Array normals;                   ///< per surface vertex, unit, outward of the solid
  std::vector<char> surface_is_outer;  ///< per surface vertex: 1 on the outer surface, 0 on the inner
  int outer_foldovers = 0;  ///< "lumen": outer-surface triangles flipped by the vertex-normal offset
};

/// Builds the wall. Throws InputError (naming spec.source) for a bad spec, a mesh that fails
/// check_mesh (closed required for "closed_wall"), a closed wall without an inner surface, more than
/// 5e7 lattice points, or a wall that keeps no tetrahedron.
MeshWall make_mesh_wall(const TriangleMesh& mesh, const MeshWallSpec& spec);

/// Layer count through the wall, measured on the built cloud (used by the tests and the log).
struct WallLayers {
  int min = 0;
  double mean = 0.0;
  int samples = 0;
};

/// For up to `max_samples` inner-surface vertices p (evenly spread) with wall direction n (minus the
/// surface normal): the kept nodes within lateral distance Delta of the line p + s n (s in [-Delta,
/// t + Delta]) span a depth range D along n; layers = 1 + floor(D / Delta). For an axis-aligned wall
/// this is the number of node planes inside the wall; for an oblique wall it is the number of such
/// planes the same depth range would hold, i.e. it measures how much of the wall the nodes span.
WallLayers measure_wall_layers(const MeshWall& wall, int max_samples);

}  // namespace vascsim
