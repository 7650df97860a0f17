#pragma once
// Boundary of a tetrahedral set: the triangles that belong to exactly one tetrahedron, oriented
// outward, and the lumped (one-third) area of the boundary around each node.

#include <array>
#include <vector>

#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

using Triangle = std::array<Index, 3>;

using Edge = std::array<Index, 2>;

/// The distinct edges of `tets`, each once as (lo, hi), sorted.
std::vector<Edge> tet_edges(const std::vector<Tet>& tets);

/// Faces of `tets` not shared by two tets, with outward orientation (#F by 3 node indices).
std::vector<Triangle> boundary_faces(const std::vector<Tet>& tets);

/// Per-node share of boundary area (m^2): a third of every boundary triangle's area whose three nodes
/// all satisfy `in_set`. #N entries.
std::vector<double> lumped_boundary_area(const Vec3Array& X, const std::vector<Triangle>& faces,
                                         const std::vector<char>& in_set);

}  // namespace vascsim
