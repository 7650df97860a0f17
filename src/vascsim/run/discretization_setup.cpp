#include "vascsim/run/discretization_setup.hpp"

#include <algorithm>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/lattice_quadrature.hpp"

namespace vascsim {

DiscretizationOptions discretization_options(const Scene& scene, const Body& body) {
  DiscretizationOptions o = scene.discretization;
  if (o.volume == VolumeRule::Simpson) o.volume_factors = simpson_volume_factors(body);
  if (o.support != DiscretizationOptions::Support::Wall) return o;
  if (!body.wall || !(body.wall->layer_spacing_m > 0.0) || !(body.cloud.spacing_m > 0.0))
    throw InputError("key 'discretization.support': 'wall' needs a body with node layers through a wall (geometry "
                     "type 'vessel' or 'tube'); use 'isotropic'");
  o.wall_normals = body.wall->outward;
  o.wall_depths = body.wall->depth_m;
  o.wall_stretch = std::max(1.0, body.cloud.spacing_m / body.wall->layer_spacing_m);
  return o;
}

}  // namespace vascsim
