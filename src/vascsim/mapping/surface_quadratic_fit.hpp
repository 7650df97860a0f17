#pragma once
// The curvature correction of a surface's linear interpolation (docs/model/22-contact.md section 22.5,
// "quadratic"): shape functions that, added to a point's barycentric weights on its triangle, make the
// interpolation exact for every displacement quadratic along the surface, and still pass through the nodes.
//
// Why: a tool's dent in the wall is curved. Interpolated linearly between the nodes the displaced surface is
// a set of chords, and a chord of a dent of radius R between nodes L apart cuts L^2 / (8 R) into the tool:
// the penalty then pushes the nodes that much deeper than the tool, which at the onset of a press is a large
// fraction of the depth (the vein's 6 Fr catheter, R = 1 mm, on a 0.3 mm lattice: 11 um against 0.1 mm), and
// how much depends on where the nodes fall under the tool.
//
// How: a moving-least-squares fit of the surface's nodes in the point's tangent plane, basis
// (1, a, b, a^2, a b, b^2) of the tangent coordinates over the radius, gives the displacement's second
// derivatives at the point; the linear interpolant of a quadratic f misses it by -sum_k beta_k q(X_k - p), q
// the quadratic part, beta_k the barycentric weights. The correction is that term of the fit, so only the
// fit's curvature enters (its value and slope would smooth the dent's edge: the fit used as the surface
// itself made the aorta's probe 3-5 % soft and moved it by 12 points between fit radii).

#include <array>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// The nodes a fit may use: those on the surface, with their rest positions and outward unit normals.
struct SurfaceNodes {
  std::vector<Index> node;  ///< node index of each entry (each node once)
  Vec3Array position_m;     ///< rest position, m
  Vec3Array normal;         ///< outward unit normal of the surface there
};

/// A point's triangle: its corners' rest positions (m) and the point's barycentric weights on them.
struct SurfaceCorners {
  std::array<Vec3, 3> position_m;
  Vec3 weight;
};

/// One point's correction: phi[k] on node[k], to add to its barycentric weights. Empty when no fit was
/// possible (the point keeps its linear interpolation).
struct SurfaceFitRow {
  std::vector<Index> node;
  std::vector<double> phi;
};

struct SurfaceQuadraticFitOptions {
  /// The support radius in units of the point's triangle's longest edge. 1.5 holds the 12-13 nodes nearest a
  /// point of a square lattice (diagonal 1.41 L), the fewest that fit six monomials from every side.
  double radius_factor = 1.5;
  double growth_factor = 1.25;  ///< the radius grows by this while the fit is not conditioned ...
  int max_growths = 4;          ///< ... at most this often; then the row is empty
  /// Conditioning of the scaled 6x6 moment matrix: smallest over largest eigenvalue at least this.
  double min_eigen_ratio = 1e-6;
  /// Only nodes whose normal lies within acos(min_normal_dot) of the point's normal: a thin wall's other
  /// face, and the far side of a crease, are not the same surface.
  double min_normal_dot = 0.5;
};

/// Corrections for `points` (rest positions, m) with their outward unit normals and triangles. With them,
/// each point's shape functions sum to one, vanish at its corners' nodes but for the corner itself when the
/// point is one, and reproduce at the point every field on the nodes that is a quadratic polynomial of its
/// tangent coordinates. Throws InputError for mismatched sizes, a degenerate triangle or invalid options.
std::vector<SurfaceFitRow> surface_curvature_rows(const SurfaceNodes& nodes, const Vec3Array& points_m,
                                                  const Vec3Array& normals,
                                                  const std::vector<SurfaceCorners>& corners,
                                                  const SurfaceQuadraticFitOptions& options = {});

}  // namespace vascsim
