#pragma once
// A vessel lattice fitted to a wall patch (geometry.fit_lattice_to_patch, docs/scene-format.md): a patch
// selects whole lattice columns and cross-sections, so at a coarse spacing its area can be far from the one
// asked (and a bonded patch's force follows its area). The fit chooses the counts around and along the
// vessel, and the lattice's phase, within a band around the counts the node spacing gives, so that either the
// strips the selected nodes stand for cover the patch (the area a spread force acts on), or the selected
// nodes reach exactly to the patch's edges (the surface a prescribed displacement holds, as nodes on the edge
// of a finite element's bonded patch do).

#include <string>

#include "vascsim/geometry/generators.hpp"

namespace vascsim {

struct LatticeFit {
  int angular_nodes = 0, axial_nodes = 0;  ///< the counts chosen (0: left to the spacing)
  double lattice_angle_deg = 0.0;          ///< the phase: a column, or the middle between two, at the centre
  double angle_error = 0.0, length_error = 0.0;  ///< selected / asked - 1 after the fit
  std::string summary;                           ///< one line for the log
};

/// A wall patch as its selector asks it: centre angle and half width (deg), centre and half length along the
/// centre-line (m).
struct PatchExtent {
  double angle_center_deg = 0.0, angle_half_width_deg = 0.0;
  double s_center_m = 0.0, s_half_length_m = 0.0;
};

/// What the fit makes equal to the asked patch.
enum class PatchFit {
  Strips,  ///< the strips of half a lattice step on either side of the selected nodes
  Edges    ///< the span of the selected nodes: columns and cross-sections on the patch's edges
};

/// The counts and phase for `patch` on a tube or swept vessel with the wall and spacing of `tube` and a
/// centre-line length_m long (the spacing gives the nominal counts). Counts are searched within 0.75-1.5
/// times the nominal ones; among those with the smallest error the closest to nominal wins.
LatticeFit fit_lattice_to_patch(const TubeSpec& tube, const PatchExtent& patch, double length_m,
                                PatchFit mode);

}  // namespace vascsim
