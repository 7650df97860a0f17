#pragma once
// Nodal quadrature weights that follow a lattice's layers (docs/model/04-volumes.md, "Simpson volumes"): the
// tet partition gives the nodes of a layered lattice the trapezoid's weights (half a layer at either
// surface), which integrate what varies linearly across the layers exactly but overestimate the energy of a
// bending field (quadratic through the layers) by half with three layers. These factors turn them into
// weights that integrate cubics exactly along the layer direction: Simpson's rule, with Simpson's 3/8 rule
// once for an odd number of layer steps.

#include <vector>

#include "vascsim/geometry/vessel_body.hpp"

namespace vascsim {

/// Closed quadrature weights on n >= 2 equally spaced points over [0, 1], exact for cubics when n >= 3 (the
/// trapezoid for n = 2).
std::vector<double> cubic_exact_weights(int n);

/// Per node, the factor that turns its tet-partition volume into its Simpson volume: through the wall of a
/// vessel with node layers (tube, vessel), along every axis of a box lattice (box, beam). Throws InputError
/// for a body without a lattice (imported meshes).
std::vector<double> simpson_volume_factors(const Body& body);

}  // namespace vascsim
