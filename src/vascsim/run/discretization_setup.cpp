#include "vascsim/run/discretization_setup.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/lattice_quadrature.hpp"

namespace vascsim {

namespace {

// The lattice's node spacing along the wall: the square root of the wall area per column and cross-section at the
// mean node radius, sqrt(r Delta_theta Delta_s), when the wall is swept along a centre-line; the generator's
// nominal spacing otherwise. A lattice fitted to a patch (geometry.fit_lattice_to_patch) differs from the nominal
// spacing by up to a factor 1.5, and its supports must follow the nodes it has, not the number that was asked.
double along_wall_spacing(const Body& body) {
  const WallCoordinates& wall = *body.wall;
  const Vec3Array& X = body.cloud.positions;
  if (!wall.has_centerline() || !(wall.angle_step_deg > 0.0) || !(wall.s_step_m > 0.0) || X.empty())
    return body.cloud.spacing_m;
  double radius = 0.0;
  for (std::size_t i = 0; i < X.size(); ++i) radius += (X[i] - wall.centerline->position(wall.s_m[i])).norm();
  radius /= static_cast<double>(X.size());
  return std::sqrt(radius * wall.angle_step_deg * std::numbers::pi / 180.0 * wall.s_step_m);
}

}  // namespace

DiscretizationOptions discretization_options(const Scene& scene, const Body& body) {
  DiscretizationOptions o = scene.discretization;
  if (o.volume == VolumeRule::Simpson) o.volume_factors = simpson_volume_factors(body);
  if (o.support != DiscretizationOptions::Support::Wall) return o;
  if (!body.wall || !(body.wall->layer_spacing_m > 0.0) || !(body.cloud.spacing_m > 0.0))
    throw InputError("key 'discretization.support': 'wall' needs a body with node layers through a wall (geometry "
                     "type 'vessel' or 'tube'); use 'isotropic'");
  o.wall_normals = body.wall->outward;
  o.wall_depths = body.wall->depth_m;
  o.wall_stretch = std::max(1.0, along_wall_spacing(body) / body.wall->layer_spacing_m);
  o.wall_thickness_m = body.wall->thickness_m;
  o.wall_layer_spacing_m = body.wall->layer_spacing_m;
  return o;
}

}  // namespace vascsim
