#include "vascsim/run/discretization_setup.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/lattice_quadrature.hpp"

namespace vascsim {

namespace {

// Per node, its cell along the wall (WallQuadrature::GaussCell): on a wall swept along a centre-line, the
// column step around it (r_i Delta_theta, perpendicular to the normal and the centre-line) by the
// cross-section step along it (Delta_s along the centre-line's tangent, longer on the outside of a bend,
// halved and shifted inwards at the wall's two ends); on an imported wall, a square of the lattice spacing in
// the tangent plane (a square's product rule does not depend on its orientation).
std::vector<DiscretizationOptions::WallCell> wall_cells(const Body& body) {
  const WallCoordinates& wall = *body.wall;
  const Vec3Array& X = body.cloud.positions;
  std::vector<DiscretizationOptions::WallCell> cells(X.size());
  const bool swept = wall.has_centerline() && wall.angle_step_deg > 0.0 && wall.s_step_m > 0.0;
  const double dtheta = wall.angle_step_deg * std::numbers::pi / 180.0, ds = wall.s_step_m;
  for (std::size_t i = 0; i < X.size(); ++i) {
    const Vec3& n = wall.outward[i];
    DiscretizationOptions::WallCell& c = cells[i];
    if (swept) {
      const Centerline& line = *wall.centerline;
      const double s = wall.s_m[i];
      const Vec3 axis = line.tangent(s);
      const Vec3 around = n.cross(axis).normalized();
      const Vec3 from_axis = X[i] - line.position(s);
      const double r = from_axis.norm();
      // A node at X - c(s) from a bending centre-line moves (1 - T'(s).(X - c)) metres per metre of arc
      // length: the outside of a bend is longer than the centre-line, the inside shorter (the frame rotates
      // without twist).
      double lo_s = std::max(s - 0.5 * ds, 0.0), hi_s = std::min(s + 0.5 * ds, wall.length_m);
      double width = dtheta, offset = 0.0;  // around the centre-line, rad
      if (!wall.cells.empty()) {            // a graded lattice: the node's own cell
        const LatticeCell& cell = wall.cells[i];
        lo_s = cell.s_lo_m, hi_s = cell.s_hi_m;
        width = (cell.theta_hi_deg - cell.theta_lo_deg) * std::numbers::pi / 180.0;
        offset = 0.5 * (cell.theta_hi_deg + cell.theta_lo_deg) * std::numbers::pi / 180.0;
      }
      const Vec3 bend = (line.tangent(hi_s) - line.tangent(lo_s)) / (hi_s - lo_s);
      const double stretch = 1.0 - bend.dot(from_axis);
      c.edges = {r * width * around, (hi_s - lo_s) * stretch * axis};
      // `around` = n x T points towards decreasing theta (theta turns from N towards B, T x N = B).
      c.centre = {-r * offset, (0.5 * (lo_s + hi_s) - s) * stretch};
    } else {
      const Vec3 t1 = n.unitOrthogonal();
      c.edges = {body.cloud.spacing_m * t1, body.cloud.spacing_m * n.cross(t1)};
    }
  }
  return cells;
}

// Per node on a graded lattice, its support's stretches (DiscretizationOptions::wall_stretches around the
// vessel, wall_axial_stretches along its centre-line, wall_axes that direction): its cell's two sides along
// the wall over the layer step, at least 1. Its cell's sides, not their mean: beside the fine window the
// cells are up to coarse / fine times longer one way than the other, and one stretch from their mean reaches
// a single step along the long side, where the quadratic fit needs two (its guard then grew a third of the
// supports of a graded vein, isotropically). Nothing on a uniform lattice, whose one stretch is every node's.
void graded_wall_supports(const Body& body, DiscretizationOptions& o) {
  const WallCoordinates& wall = *body.wall;
  if (wall.cells.empty()) return;
  const double radius = mean_node_radius_m(body), D = wall.layer_spacing_m;
  for (std::size_t i = 0; i < wall.cells.size(); ++i) {
    const LatticeCell& c = wall.cells[i];
    // A cell at a vessel's end is half a step long; the spacing there is its neighbour's full step.
    const bool end = wall.s_m[i] <= c.s_lo_m || wall.s_m[i] >= c.s_hi_m;
    const double ds = (c.s_hi_m - c.s_lo_m) * (end ? 2.0 : 1.0);
    const double around = radius * (c.theta_hi_deg - c.theta_lo_deg) * std::numbers::pi / 180.0;
    o.wall_stretches.push_back(std::max(1.0, around / D));
    o.wall_axial_stretches.push_back(std::max(1.0, ds / D));
    o.wall_axes.push_back(wall.centerline->tangent(wall.s_m[i]));
  }
}

}  // namespace

DiscretizationOptions discretization_options(const Scene& scene, const Body& body) {
  DiscretizationOptions o = scene.discretization;
  if (o.volume == VolumeRule::Simpson) o.volume_factors = simpson_volume_factors(body);
  if (o.support != DiscretizationOptions::Support::Wall) return o;
  if (!body.wall || !(body.wall->layer_spacing_m > 0.0) || !(body.cloud.spacing_m > 0.0))
    throw InputError(
        "key 'discretization.support': 'wall' needs a body with node layers through a wall (geometry "
        "type 'vessel' or 'tube'); use 'isotropic'");
  o.wall_normals = body.wall->outward;
  o.wall_depths = body.wall->depth_m;
  o.wall_stretch = std::max(1.0, along_wall_spacing_m(body) / body.wall->layer_spacing_m);
  graded_wall_supports(body, o);
  o.wall_thickness_m = body.wall->thickness_m;
  o.wall_layer_spacing_m = body.wall->layer_spacing_m;
  if (o.wall_quadrature == DiscretizationOptions::WallQuadrature::GaussCell) o.wall_cells = wall_cells(body);
  return o;
}

}  // namespace vascsim
