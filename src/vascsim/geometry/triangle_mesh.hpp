#pragma once
// Triangle surface meshes (imported vessel surfaces, wall surfaces): validation, consistent outward
// orientation, vertex normals, and closest-point / signed-distance queries accelerated by a BVH.

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

using Triangle = std::array<Index, 3>;

/// An indexed triangle mesh. Vertices in m. When oriented, every triangle (a, b, c) is counter-clockwise
/// seen from the side its normal (b - a) x (c - a) points to.
struct TriangleMesh {
  Vec3Array vertices;               ///< #V positions, m
  std::vector<Triangle> triangles;  ///< #F vertex indices into `vertices`
};

/// Throws InputError with one line "NAME: reason (first offending triangle/edge/vertex, coordinates)"
/// if the mesh has no triangles, an index out of range, a non-finite coordinate, a degenerate triangle
/// (a repeated index, or area <= 1e-12 bbox_diagonal^2), a non-manifold edge (> 2 triangles), or is
/// not orientable; with require_closed, also if any edge belongs to one triangle only (open boundary).
/// Inconsistent but fixable orientation is accepted (orient_outward fixes it).
void check_mesh(const TriangleMesh& mesh, const std::string& name, bool require_closed);

/// Connected components (through shared edges) of a mesh, as orient_outward left them.
struct MeshComponents {
  std::vector<Index> of_triangle;  ///< #F component id per triangle
  std::vector<char> closed;        ///< per component: every edge shared by exactly two triangles
  /// Per component: the number of closed components that enclose it (0 = outermost). A component with
  /// odd depth is an inner surface (e.g. the lumen side of a closed wall).
  std::vector<int> nesting_depth;
  int count() const { return static_cast<int>(closed.size()); }
};

/// Orients a mesh that passed check_mesh: (1) consistent orientation per component by breadth-first
/// flips; (2) each component's enclosed volume made positive (open components are capped by a fan
/// from each boundary loop's centroid for this measure); (3) closed components enclosed by an odd
/// number of others are flipped, so that a nested pair bounds a solid with outward normals.
MeshComponents orient_outward(TriangleMesh& mesh);

/// Signed enclosed volume (divergence theorem), m^3: positive for a closed outward-oriented surface.
/// For a nested pair oriented by orient_outward it is the volume of the solid between them.
double enclosed_volume(const TriangleMesh& mesh);

/// Edges that belong to one triangle only, directed as in that triangle.
std::vector<std::array<Index, 2>> boundary_edges(const TriangleMesh& mesh);

/// Length of the axis-aligned bounding box diagonal, m (0 for an empty mesh).
double bounding_box_diagonal(const TriangleMesh& mesh);

/// Which part of the closest triangle the closest point lies on.
enum class MeshFeature { face, edge, vertex };

struct ClosestPoint {
  bool found = false;         ///< false if nothing lies within the query's max_distance
  Vec3 point = Vec3::Zero();  ///< closest point on the surface, m
  double distance = std::numeric_limits<double>::infinity();  ///< |p - point|, m
  /// +distance on the side the normals face, -distance on the other (pseudo-normal test), m.
  double signed_distance = std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::Zero();  ///< unit pseudo-normal of the closest feature
  Index triangle = -1;         ///< the triangle the closest point was found on
  MeshFeature feature = MeshFeature::face;
  bool on_boundary = false;  ///< the closest feature is a boundary edge or a vertex on the boundary
};

/// Closest-point and signed-distance queries against a fixed, oriented mesh. The sign uses the
/// angle-weighted pseudo-normal of the closest feature (face, edge or vertex), which is exact for a
/// closed, consistently oriented, non-self-intersecting mesh (Baerentzen & Aanaes 2005, IEEE TVCG 11(3)).
/// Queries are const and thread-safe.
class MeshDistance {
 public:
  /// Copies `mesh` (which should be oriented) and builds a bounding-volume hierarchy over its triangles.
  explicit MeshDistance(const TriangleMesh& mesh);

  /// Closest surface point to p (m) among points within max_distance (m); found = false if none.
  ClosestPoint closest(const Vec3& p, double max_distance = std::numeric_limits<double>::infinity()) const;

  /// Signed distance of p (m): positive on the side the normals face.
  double signed_distance(const Vec3& p) const { return closest(p).signed_distance; }

  const TriangleMesh& mesh() const { return mesh_; }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    Index first = 0;   ///< leaf: first entry in order_; inner: the left child
    Index right = -1;  ///< inner: the right child
    Index count = 0;   ///< leaf: number of triangles; inner: 0
  };
  Index build(Index begin, Index end, const Vec3Array& centroids);

  TriangleMesh mesh_;
  std::vector<Node> nodes_;
  std::vector<Index> order_;                    // triangle ids, grouped by leaf
  Vec3Array face_normal_;                       // #F unit
  std::vector<std::array<Index, 3>> tri_edge_;  // #F edge ids of (v0 v1), (v1 v2), (v2 v0)
  Vec3Array edge_normal_;                       // per edge: normalised sum of its faces' normals
  std::vector<char> edge_boundary_;
  Vec3Array vertex_normal_;  // angle-weighted
  std::vector<char> vertex_boundary_;
};

}  // namespace vascsim
