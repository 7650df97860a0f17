#pragma once
// Procedural node clouds: a box lattice (beams, cantilever) and a straight hollow tube (vessel wall).

#include <cstdint>

#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

struct BoxSpec {
  Vec3 min_m = Vec3::Zero();
  Vec3 max_m = Vec3::Ones();
  Eigen::Vector3i cells = Eigen::Vector3i::Constant(4);  ///< lattice cells per axis (>= 1)
  double jitter = 0.0;     ///< random offset of every node, fraction of the cell edge (0 <= j < 0.3)
  std::uint64_t seed = 1;  ///< jitter random seed
};

/// Regular (optionally jittered) lattice of (cells+1) nodes per axis; every cell is split into 6
/// tetrahedra around its main diagonal (Kuhn split), which is conforming across cells.
NodeCloud make_box(const BoxSpec& spec);

struct TubeSpec {
  double outer_radius_m = 1.5e-3;
  double wall_thickness_m = 0.3e-3;
  double length_m = 20e-3;
  double node_spacing_m = 0.15e-3;  ///< target spacing Delta along all three directions
  int min_layers =
      3;  ///< minimum node layers through the wall (docs/model/00-design-decisions.md, decision 2)
  /// A lattice line (a column of nodes along the axis) runs at this angle, deg (theta from +x towards +y):
  /// the lattice is turned by less than half a column so that a patch centred here is symmetric.
  double lattice_angle_deg = 0.0;
  /// Lattice counts around and along the tube when > 0 (a lattice fitted to a patch, geometry/lattice_fit);
  /// 0: from node_spacing_m (lattice_columns, lattice_cross_sections).
  int angular_nodes = 0, axial_nodes = 0;
};

/// Angle (rad) of the first of `columns` equally spaced lattice angles so that one of them is
/// `lattice_angle_deg`: the smallest turn of the plain lattice (whose column 0 is at angle 0), and exactly 0
/// when the plain lattice already has a column there.
double lattice_phase_rad(double lattice_angle_deg, int columns);

/// Columns of nodes around a wall of mid-wall radius r_mid_m: `asked` when > 0, else round(2 pi r_mid /
/// spacing); at least 8. Shared by the tube, the swept vessel and the lattice fit.
int lattice_columns(double r_mid_m, double spacing_m, int asked = 0);
/// Cross-sections along a length_m long axis or centre-line: `asked` when > 0, else round(L / spacing) + 1;
/// at least 2.
int lattice_cross_sections(double length_m, double spacing_m, int asked = 0);

/// Hollow cylinder wall along +z from z = 0 to z = length, centred on the z axis. Node layers at the
/// inner and outer surface (so boundary conditions can act on surface nodes), max(min_layers,
/// ceil(t/Delta)+1) layers through the wall, round(2 pi r_mid / Delta) nodes around, round(L/Delta)+1
/// along, the angles turned by lattice_phase_rad. Every (r, theta, z) cell is split into 6 tetrahedra.
NodeCloud make_tube(const TubeSpec& spec);

}  // namespace vascsim
