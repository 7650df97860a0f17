#pragma once
// Inverted material: a virtual tetrahedron whose signed volume changed sign, or a node whose MLS deformation
// gradient has det F_i <= 0. The energy (SVK and the hyperelastic laws at small strain) is not meant for
// inverted elements, so a state with any is no solution, whatever its residual says. Every model is checked
// here, in one place: quasi_static retries the load step in smaller steps, the runs stop with a
// NumericalError naming the step (run/simulation.cpp).

#include <string>

#include "vascsim/model/problem.hpp"

namespace vascsim {

struct InversionReport {
  Index inverted_tets = 0;  ///< virtual tetrahedra whose volume changed sign (or vanished)
  Index first_tet = -1;
  Index inverted_nodes = 0;  ///< nodes with det F_i <= 0
  Index first_node = -1;
  double min_det_f = 1.0;  ///< the smallest det F_i
  bool any() const { return inverted_tets > 0 || inverted_nodes > 0; }
  /// "3 virtual tetrahedra inverted (the first: 17), 2 nodes with det F <= 0 (the first: node 5, det F =
  /// -0.2)"
  std::string describe() const;
};

/// Checks configuration x (m) of the problem's body.
InversionReport check_inversion(const Problem& problem, const Vec3Array& x);

}  // namespace vascsim
