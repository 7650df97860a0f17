#pragma once
// Quadrature points on a closed triangle surface, for contact on the wall's surface rather than at the nodes
// (docs/model/22-contact.md section 22.5). Each triangle is split into m x m congruent sub-triangles (m =
// ceil(longest edge / spacing)); a sample sits at each sub-triangle's centroid and carries its area. Where
// the three vertex normals agree with the face (a smooth wall), the sample is lifted off the flat triangle
// onto the curved surface the normals describe: Phong tessellation with shape factor 1/2, which puts a
// chord's points on the circle through its ends to second order in the chord's angle (the flat chord of a 0.3
// mm lattice on a 1.5 mm vein lies up to 7.5 um inside the wall, as much as a tenth of the first 0.1 mm of a
// push).

#include <vector>

#include "vascsim/geometry/vessel_body.hpp"

namespace vascsim {

struct SurfaceSamples {
  Vec3Array positions;          ///< rest positions, m
  Vec3Array normals;            ///< unit, outward of the solid (interpolated vertex normals)
  std::vector<double> area_m2;  ///< surface area each sample stands for, m^2 (they sum to the mesh's area)
  std::vector<Index> triangle;  ///< the triangle each sample lies on
  Vec3Array barycentric;        ///< its barycentric coordinates there (weights of the triangle's vertices)
  std::vector<char> smooth;    ///< 1 where its triangle is smooth (the sample lifted onto the curved surface)
  int subdivisions_max = 1;    ///< the largest m used
  double spacing_min_m = 0.0;  ///< the finest spacing a triangle was sampled at (own_edge_fraction), m
};

/// Samples `surface` at about `spacing_m` (> 0). With own_edge_fraction > 0 a triangle is sampled no farther
/// apart than that fraction of its own mean edge (m >= ceil(longest edge / (fraction x mean edge))): a graded
/// lattice's fine triangles then get as many samples as a uniform lattice's, where one spacing from the whole
/// surface's mean edge would leave them one or two. Normals that differ from the face normal by more than 30
/// degrees (a crease: a box's edge, a vessel's rim) keep that triangle flat. Throws InputError for a
/// non-positive spacing, a negative fraction or more than 2e7 samples.
SurfaceSamples sample_surface(const RenderSurface& surface, double spacing_m, double own_edge_fraction = 0.0);

}  // namespace vascsim
