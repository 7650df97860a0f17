#pragma once
// The scene's discretisation options completed from the body it applies to: the wall frame of supports that
// follow the wall and the factors of Simpson volumes (docs/model/03-neighbourhoods.md section 3.1 and
// docs/model/04-volumes.md section 4.3). Every caller that builds a Discretization from a scene goes through
// here, so a scene key means the same thing everywhere.

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

/// scene.discretization with wall_normals / wall_stretch (support: wall) and volume_factors (volume: simpson)
/// filled from `body`. Throws InputError naming the key when the body cannot give them.
DiscretizationOptions discretization_options(const Scene& scene, const Body& body);

}  // namespace vascsim
