#pragma once
// Frictionless one-sided contact between the problem's tools and the free nodes, by an active set (the
// equilibrium solvers, docs/model/22-contact.md section 22.3): a node that enters a tool is put on its
// surface and its normal degree of freedom is held there; residuals, search directions and preconditioned
// vectors are filtered by I - n n^T (the "modified PCG" of Baraff & Witkin 1998), so it can still slide along
// the tool. A contact whose normal reaction lambda = -r.n pulls on the tool is released. The tool force is
// sum lambda n over its contacts.

#include <vector>

#include "vascsim/model/free_dofs.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {

class ContactActiveSet {
 public:
  /// With `tools_meet_nodes` false the set holds no tools (they meet the wall's surface instead,
  /// embedded_contact.hpp) and every call is a no-op.
  ContactActiveSet(const Problem& problem, const FreeDofs& free, bool tools_meet_nodes = true);

  /// No tools: every other call is a no-op.
  bool empty() const { return geometry_.empty(); }
  /// Places tool o's contact geometry (the solve that follows sees it).
  void place(std::size_t o, const constraints::Capsule& geometry) { geometry_.at(o) = geometry; }
  const constraints::Capsule& geometry(std::size_t o) const { return geometry_.at(o); }

  /// Removes the normal component at nodes in contact.
  void filter(Vec3Array& v) const;
  /// Puts every node in contact on its tool's surface at the current geometry; with `add`, also takes in the
  /// free nodes that penetrate a tool. Returns the number taken in.
  int project(Vec3Array& x, bool add);
  /// The contact curvature term of the Lagrangian's Hessian applied to p, added to Hp (see the .cpp).
  void add_curvature(const Vec3Array& x, const Vec3Array& p, Vec3Array& Hp) const;
  /// lambda_i = -r_i . n_i at every contact (r the unfiltered residual).
  void update_lambdas(const Vec3Array& r);
  /// Releases the contacts whose reaction pulls (lambda = -r.n < 0); returns how many.
  int release_pulling(const Vec3Array& r);
  /// Per tool: sum lambda n (force on the tissue), its moment about tool_points[o], the contact count.
  std::vector<ObstacleLoad> loads(const Vec3Array& r, const Vec3Array& x,
                                  const std::vector<Vec3>& tool_points) const;

  bool in_contact(Index i) const { return contact_of_[static_cast<std::size_t>(i)] >= 0; }
  int tool_of(Index i) const { return contact_of_[static_cast<std::size_t>(i)]; }
  const Vec3& normal(Index i) const { return normal_[static_cast<std::size_t>(i)]; }
  double lambda(Index i) const { return lambda_[static_cast<std::size_t>(i)]; }
  int active() const;
  int pulling() const;

 private:
  const FreeDofs& free_;
  std::vector<constraints::Capsule> geometry_;  // per tool
  std::vector<int> contact_of_;                 // per node: tool in contact, -1 none
  Vec3Array normal_;                            // per node in contact: unit normal out of the tool
  std::vector<double> lambda_;                  // per node in contact: normal force -r.n at the last iterate
};

}  // namespace vascsim
