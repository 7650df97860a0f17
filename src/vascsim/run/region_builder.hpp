#pragma once
// Turning the scene's regions into the problem's Regions: each selector (box, cylinder end, wall patch,
// surface patch, all) picks nodes of the discretised body, and its boundary condition becomes a prescribed
// displacement, a fixed support or a force spread over the patch by area.

#include <vector>

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/problem.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

/// Arc length (m) of a wall patch's centre: s_center_fraction of the length, or s_center_m.
double wall_patch_center_s(const SelectorSpec& s, const WallCoordinates& wall);

/// Selects the nodes of every region and turns the scene's boundary conditions into Regions. Throws
/// InputError naming the region for a selector that selects nothing or does not fit the geometry.
std::vector<Region> build_regions(const Scene& scene, const Discretization& disc, const Body& body);

}  // namespace vascsim
