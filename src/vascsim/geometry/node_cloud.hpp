#pragma once
// The rest-state node cloud of a body: interior nodes (the point primitives) and the virtual
// tetrahedra built over them (paper section 2.2.2). Produced by the generators in this folder.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// Four node indices with positive signed volume (a, b, c, d): (b-a).((c-a)x(d-a)) > 0.
using Tet = std::array<Index, 4>;

/// Axis-aligned hollow cylinder description attached to a tube cloud: the axis is the z axis
/// through the origin, the wall spans z in [0, length].
struct TubeShape {
  double outer_radius_m = 0.0;
  double inner_radius_m = 0.0;
  double length_m = 0.0;
  int radial_layers = 0;  ///< node layers through the wall, inner and outer surface included
};

/// How a structured wall lattice numbers its nodes (tubes and swept vessels): node (layer, column, section)
/// has index layer + layers (column + columns section). Columns run around the centre-line and close on
/// themselves (column `columns` is column 0); sections run along it from one end to the other; layers go from
/// the inner (lumen) surface to the outer one. Coarser levels of a solver read the lattice from it
/// (wall_coarse_space.hpp).
struct WallLatticeNumbering {
  int layers = 0, columns = 0, sections = 0;
  Index id(int layer, int column, int section) const {
    return static_cast<Index>(layer +
                              layers * (((column % columns) + columns) % columns + columns * section));
  }
};

struct NodeCloud {
  Vec3Array positions;                                  ///< rest positions X_i, #N, m
  std::vector<Tet> tets;                                ///< virtual tetrahedra, positively oriented
  double spacing_m = 0.0;                               ///< the generator's nominal node spacing Delta, m
  std::string kind;                                     ///< "box", "tube", ...
  std::optional<TubeShape> tube;                        ///< set for tubes (region selectors use it)
  std::optional<WallLatticeNumbering> wall_lattice;     ///< set for tubes and swept vessels
  Eigen::AlignedBox3d box;                              ///< set for boxes: the rest bounding box, m
  Eigen::Vector3i box_cells = Eigen::Vector3i::Zero();  ///< set for boxes: lattice cells per axis
};

/// Signed volume of tetrahedron (a, b, c, d), m^3.
inline double signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

}  // namespace vascsim
