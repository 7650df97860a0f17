#pragma once
// The contacts seen through the preconditioner's factor P (docs/model/24-implicit.md section 24.2-24.3).
//
// Z = P^{-1} E (E: the unit vectors of the contact nodes' 3 m degrees of freedom; per node from the shared
// NodeCompliance cache, which solves only nodes it has not seen with this P) gives the contact-node
// compliance C = E^T Z (3m x 3m), and from it:
//
// - the contact correction of CG: on the contact-filtered Newton system (modified PCG) a factor of the
//   unconstrained matrix converges slowly, since it knows nothing of the m normal constraints N x = 0. Its
//   P-orthogonal projection onto them,
//       z = P^{-1} r - Z N_b^T W^{-1} N P^{-1} r,     W = N_b C N_b^T  (m x m, the contact compliance),
//   is the exact inverse of the constrained system when P is the Newton matrix;
// - the tool's linearised response (tool_stiffness): the force change when the tool translates by dp with the
//   contact set held, including the turn of each contact force as its node slides on the curved tool.
//
// N_b (m x 3m) holds each contact's normal in its node's block. The normals are the current ones at every
// use; only Z depends on the set and P.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/equilibrium_preconditioner.hpp"
#include "vascsim/model/node_compliance.hpp"

namespace vascsim {

class ContactCorrection {
 public:
  ContactCorrection(const FreeDofs& free, const ContactActiveSet& contacts)
      : free_(free), contacts_(contacts) {}
  /// Refreshes Z if the contact nodes or the preconditioner changed (from `compliance`, which solves the
  /// nodes it lacks), and W with the current normals. False when there is nothing to correct (no contacts, or
  /// a preconditioner without multi-column solves).
  bool update(const EquilibriumPreconditioner& preconditioner, NodeCompliance& compliance);
  /// z -= Z N_b^T W^{-1} (N z): z (per node, P^{-1} r) projected P-orthogonally onto N z = 0.
  void apply(Vec3Array& z) const;
  bool valid() const { return valid_; }
  /// The contact nodes of the last update, in free-node order.
  const std::vector<Index>& nodes() const { return nodes_; }
  /// W (m x m), m/N.
  const Eigen::MatrixXd& compliance() const { return W_; }
  /// d(force of the contacts in `mask` on the tissue)/d(translation of their tool), N/m (3 x 3): the
  /// linearised frictionless contact problem with the set held, from the contact-node compliance C, the
  /// normals, the normal forces lambda and each contact's curvature (the force lambda n turns by lambda H du
  /// as the node slides by du on the tool, H = (I - n n^T - e e^T) / d). Other contacts hold. Zero when
  /// invalid. x: the current positions (where each contact node touches the tool).
  Mat3 tool_stiffness(const std::vector<char>& mask, const Vec3Array& x) const;

 private:
  Mat3 curvature(Index node, const Vec3& x) const;  // H of the node's contact at its position x, 1/m

  const FreeDofs& free_;
  const ContactActiveSet& contacts_;
  std::vector<Index> nodes_;
  long long version_ = -1;
  Eigen::MatrixXd Z_, C_, W_, Nb_;  // n x 3m, 3m x 3m, m x m, m x 3m
  Eigen::LDLT<Eigen::MatrixXd> W_ldlt_;
  bool valid_ = false;
};

}  // namespace vascsim
