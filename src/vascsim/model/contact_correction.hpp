#pragma once
// Makes the conjugate-gradient preconditioner respect the contacts (docs/model.md section 24.2). CG on the
// contact-filtered Newton system (modified PCG) with a factor P of the unconstrained matrix converges slowly:
// P knows nothing of the m normal constraints N x = 0 at the contact nodes. The P-orthogonal projection onto
// them,
//     z = P^{-1} r - C W^{-1} N P^{-1} r,      C = P^{-1} N^T,  W = N C  (m x m, the contact compliance),
// is the exact inverse of the constrained system when P is the Newton matrix, for m back-solves (one
// multi-column solve) whenever the contact set or P changes. The same W is the contact-space compliance that
// the haptic linearisation needs.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/equilibrium_preconditioner.hpp"

namespace vascsim {

class ContactCorrection {
 public:
  ContactCorrection(const FreeDofs& free, const ContactActiveSet& contacts) : free_(free), contacts_(contacts) {}
  /// Rebuilds C and W if the contact set or the preconditioner changed. False when there is nothing to correct
  /// (no contacts, or a preconditioner without multi-column solves).
  bool update(const EquilibriumPreconditioner& preconditioner);
  /// z -= C W^{-1} (N z): z (per node, P^{-1} r) projected P-orthogonally onto N z = 0.
  void apply(Vec3Array& z) const;
  /// The contact nodes and normals C and W were built with, and W (m x m, m/N).
  const std::vector<Index>& nodes() const { return nodes_; }
  const Vec3Array& normals() const { return normals_; }
  const Eigen::MatrixXd& compliance() const { return W_; }

 private:
  const FreeDofs& free_;
  const ContactActiveSet& contacts_;
  std::vector<Index> nodes_;
  Vec3Array normals_;
  long long version_ = -1;
  Eigen::MatrixXd C_, W_;
  Eigen::LDLT<Eigen::MatrixXd> W_ldlt_;
  bool valid_ = false;
};

}  // namespace vascsim
