#pragma once
// Vessel wall node cloud from a real surface mesh: an axis-aligned cubic lattice over the wall solid
// (the shell of thickness t outside a lumen surface, or the solid between the inner and outer surfaces
// of a closed wall mesh) whose points near a wall surface are snapped onto it (in the spirit of
// isosurface stuffing, Labelle & Shewchuk 2007), with the Kuhn virtual tetrahedra of the lattice
// filtered for quality, plus a closed wall surface for rendering through the MLS map.
//
// Method: a lattice point inside the solid within Delta / 2 of a wall surface, or outside the solid
// within Delta of it, moves to the closest surface point (for "lumen": the closest lumen point, or the
// point at distance t along the lumen's closest-point ray for the outer surface); points further
// outside are dropped, and so are points beyond an opening of an open lumen (the rims stay a lattice
// staircase). Snapped nodes closer than 0.3 Delta are merged. A Kuhn tet of the lattice is kept if
// its four vertices are distinct nodes, its quality 6 sqrt(2) V / l_rms^3 is >= 0.1 (Kuhn tets: 0.657),
// its centroid lies in the solid and no edge midpoint leaves it by more than 0.1 Delta; nodes in no tet
// are dropped. Guarantees: every node pair >= 0.3 Delta apart (interior lattice nodes are >= Delta / 2
// from every snapped node); every tet positively oriented with quality >= 0.1. Measured: the tet
// volume is within 2 % of the wall volume on closed tubes at Delta = t / 3 (any axis direction).

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
  /// Requested lattice spacing Delta, m; reduced to t / min_layers if larger. With nodes snapped onto
  /// both surfaces an axis-aligned wall then holds min_layers + 1 node planes, and measure_wall_layers
  /// reports >= min_layers on tubes at any axis direction and on the bundled aorta (t / (min_layers -
  /// 1) measured min_layers - 1 in places).
  double node_spacing_m = 0.5e-3;
  int min_layers = 3;           ///< minimum node layers through the thinnest wall (>= 2)
  std::string source = "mesh";  ///< name used in error messages (the file name)
};

struct MeshWall {
  /// kind "mesh_wall", spacing_m = lattice spacing Delta, box = bounding box of the nodes; tets are
  /// Kuhn tets of the lattice cubes over the snapped nodes, positively oriented, quality >= 0.1.
  NodeCloud cloud;
  /// Per node: distance from the lumen (inner) surface into the wall, m. In [0, t] for "lumen": exactly
  /// 0 on the lumen, exactly t on the outer surface, in [Delta / 2, t - Delta / 2] for interior nodes.
  /// For "closed_wall" it is the distance to the nearest inner surface: exactly 0 on it, >= thickness_m
  /// on the outer surface (more where the wall is thicker than its thinnest point).
  std::vector<double> depth_m;
  /// Per node: unit wall normal pointing away from the lumen (towards the outer surface).
  Vec3Array outward;
  /// Per node: 1 if snapped onto the lumen (inner) surface, 2 if snapped onto the outer surface, 0
  /// for an interior lattice node (which lies >= Delta / 2 from both surfaces).
  std::vector<char> node_surface;
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
