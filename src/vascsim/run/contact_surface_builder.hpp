#pragma once
// Builds the wall's contact surface for embedded contact (model/contact_surface.hpp, docs/model/22-contact.md
// section 22.5) from the body's render surface: samples between the vertices (geometry/surface_samples.hpp)
// and their shape functions over the nodes, either
//   "interpolated": the barycentric weights of the triangle's vertices, where each vertex is a node (the
//                   swept vessels' surfaces are their outer and inner node layers), or
//   "quadratic":    a quadratic fit of the surface's nodes round each sample
//   (mapping/surface_quadratic_fit.hpp),
//                   on smooth triangles whose vertices are nodes; the barycentric weights elsewhere, or
//   "mls":          the MLS map of the rendered surface (mapping/mls_map.hpp), for any surface.
// "interpolated" and "quadratic" fall back to "mls" for a triangle whose vertices are not all nodes. Every
// node below the surface is also a sample of its own (it must not enter a tool either; see the .cpp).

#include <memory>

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/model/contact_surface.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

struct ContactSurfaceReport {
  Index samples = 0;
  Index interpolated = 0;      ///< samples with barycentric shape functions
  Index quadratic = 0;         ///< samples with the quadratic fit's shape functions
  Index node_samples = 0;      ///< nodes below the surface, samples of their own
  double spacing_m = 0.0;      ///< the spacing asked, or a third of the surface's mean edge, m
  double spacing_min_m = 0.0;  ///< the finest a triangle was sampled at (a third of its own mean edge), m
  double stiffness_pa_per_m = 0.0;
};

/// Throws InputError when the body has no surface.
std::shared_ptr<const ContactSurface> build_contact_surface(const Scene& scene, const Body& body,
                                                            const Discretization& disc,
                                                            ContactSurfaceReport& report);

}  // namespace vascsim
