#pragma once
// The coarse level of the wall multigrid (wall_multigrid.hpp): every second column around the centre-line and
// every second cross-section along it of a structured wall lattice (NodeCloud::wall_lattice: tubes and swept
// vessels, uniform or graded), with all of its layers through the wall. A fine node takes the displacement of
// the coarse nodes of its own layer that bracket it, linearly in each direction (bilinear in column and
// section), weighted by its rest distances to them along the lattice line. The wall is thin (three to five
// layers): coarsening only along it keeps the through-wall fields exact on the coarse level, and the
// interpolated fields are continuous, so the Galerkin coarse operator holds the wall's bending as the fine
// one does.
//
// Prescribed nodes take no part: they have no unknowns, and a fine node bracketed by one interpolates from
// the free coarse node alone (the prescribed one's share of the displacement is zero).

#include <vector>

#include "vascsim/model/discretization.hpp"
#include "vascsim/model/nodal_prolongation.hpp"

namespace vascsim {

/// Whether the discretisation's nodes form a wall lattice this level can coarsen (at least 4 columns and 3
/// cross-sections).
bool has_wall_lattice(const Discretization& disc);

/// The prolongation from the coarse wall lattice; `constrained` (per node) marks the prescribed nodes. Throws
/// std::invalid_argument when has_wall_lattice is false.
NodalProlongation wall_coarse_space(const Discretization& disc, const std::vector<char>& constrained);

}  // namespace vascsim
