#pragma once
// Node positions along one lattice axis that are fine inside a window and coarsen geometrically outside it
// (geometry.refine, docs/scene-format.md): a graded swept-vessel lattice puts its nodes where a load acts.
// Inside the window the steps are equal and the window's two edges are nodes, so a wall patch of the window's
// extent has its outermost nodes on its edges; outside, each step is `growth` times the previous one until it
// reaches the coarse spacing, and all outside steps are scaled by one factor so that they end exactly at the
// axis's ends.

#include <vector>

namespace vascsim {

struct AxisGrading {
  double fine_m = 0.0;    ///< the step inside the window (rounded so that a whole number of steps fill it)
  double coarse_m = 0.0;  ///< the largest step outside (before the final scaling)
  double growth = 1.2;    ///< ratio of two successive steps outside the window, > 1
};

/// Positions from 0 to `length` (both included). The window runs from breaks.front() to breaks.back()
/// (clipped to the axis); every break is a node, and each span between two breaks is filled by equal steps of
/// about `g.fine_m`. Throws InputError for a bad window or grading.
std::vector<double> graded_line(double length, std::vector<double> breaks, const AxisGrading& g);

/// Positions around a closed axis of the given period (an angle around a centre-line, as an arc length at the
/// mean radius): the window (breaks as for graded_line, shorter than the period) first, from breaks.front(),
/// then the rest of the period graded from both of the window's edges towards the point opposite. The values
/// run from breaks.front() to below breaks.front() + period.
std::vector<double> graded_circle(double period, std::vector<double> breaks, const AxisGrading& g);

}  // namespace vascsim
