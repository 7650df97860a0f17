#pragma once
// Vertex normals of a triangle mesh: one rule for every use (the offset of an imported lumen, the rest and
// deformed render surfaces).
//
// Weighting: each incident face's unit normal is weighted by the face's angle at the vertex (Thuermer &
// Wuethrich 1998). Unlike area weighting it does not depend on how a polygon is split into triangles:
// splitting a quad along either diagonal gives the same normal at all four corners, because the corner
// angles of the two triangles add up to the quad's angle. Area weighting tilts the normals of a swept
// vessel's quads towards the diagonal, and would make the offset of an irregular lumen mesh depend on its
// triangle sizes. The cost (one atan2 per triangle corner) is small next to the surface map.

#include <array>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// #V unit vertex normals into `normals` (resized). triangles: #F vertex triples, counter-clockwise seen
/// from the side the normals point to; positions_m: #V, m. A vertex without a face of non-zero area gets
/// a zero normal. Throws InputError for a triangle vertex out of range.
void vertex_normals(const std::vector<std::array<Index, 3>>& triangles, const Vec3Array& positions_m,
                    Vec3Array& normals);

/// The same, returned.
inline Vec3Array vertex_normals(const std::vector<std::array<Index, 3>>& triangles,
                                const Vec3Array& positions_m) {
  Vec3Array n;
  vertex_normals(triangles, positions_m, n);
  return n;
}

}  // namespace vascsim
