#pragma once
// What each region's selector actually picked, beside what the scene asked (summary.json "regions"). A node
// stands for the strip of half a lattice step on either side of it, so a wall patch of n columns spans
// n angle steps: the report gives the node count, the angular and axial extent and centre of those strips
// and their surface area (or, on a lattice fitted to the patch's edges, of the nodes' own span, the surface
// a prescribed displacement holds); a surface patch its area; a one-line warning names the region and the key
// when what was selected differs from what was asked by more than the tolerance below.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/problem.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

/// Largest accepted mismatch of a selected extent (angle, length, centre offset) relative to the asked
/// width: a tenth, i.e. less than one lattice column of a patch that is 10 columns wide. Areas are 2-D:
/// (1 + 0.1)^2 - 1 = 21 %.
inline constexpr double kSelectionTolerance = 0.1;

struct RegionSelection {
  std::string name;
  /// {"name", "selector", "nodes", "asked": {...}, "selected": {...}, "warnings": [...]}; units m, m^2, deg.
  nlohmann::json report;
  /// One line per mismatch, each naming the region and the scene key that sets the mismatched extent.
  std::vector<std::string> warnings;
};

/// One report per region, in scene order (`regions` as build_regions made them from `scene`).
std::vector<RegionSelection> describe_selections(const Scene& scene, const Discretization& disc,
                                                 const Body& body, const std::vector<Region>& regions);

}  // namespace vascsim
