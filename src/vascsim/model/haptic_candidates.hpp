#pragma once
// The candidate contacts a frame hands to the haptic thread (docs/haptics.md, "Candidate contacts"): the
// nodes a tool touches and the free nodes within a short gap of it, nearest first, with their contact-space
// compliance W = N P^{-1} N^T (W_cd = n_c^T C_cd n_d from the shared NodeCompliance cache, which solves only
// the candidates it has not seen with this factor), so that the 1 kHz loop can re-solve the unilateral
// contact as the tool moves between frames and contacts open or close.

#include <vector>

#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/model/equilibrium_preconditioner.hpp"
#include "vascsim/model/node_compliance.hpp"

namespace vascsim {

class HapticCandidates {
 public:
  /// max_candidates: how many the haptic thread takes; reach_m: the largest gap of a candidate that is not in
  /// contact (it must exceed how far the tool moves between two frames).
  HapticCandidates(const FreeDofs& free, int max_candidates, double reach_m)
      : free_(free), max_(max_candidates), reach_(reach_m) {}

  /// The candidates of tool `tool` at positions x, and their W from `preconditioner` through `compliance`,
  /// into `lin`. False when the preconditioner has no multi-column solves (then `lin` has no candidates).
  bool fill(std::size_t tool, const ContactActiveSet& contacts, const Vec3Array& x,
            const EquilibriumPreconditioner& preconditioner, NodeCompliance& compliance,
            ToolLinearization& lin);

 private:
  const FreeDofs& free_;
  int max_;
  double reach_;
};

}  // namespace vascsim
