#pragma once
// Preconditioners of the equilibrium solvers' conjugate gradients (newton_equilibrium.hpp): z = P^{-1} r on
// the free nodes, with P a sparse factorisation of a matrix close to the Newton matrix (the tangent
// stiffness, plus M/h^2 for backward Euler). The solver filters contact normals around it.

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "vascsim/model/free_dofs.hpp"

namespace vascsim {

/// The Newton matrix applied to a vector (per node; the solver's contact filter included): out = H v.
using NewtonOperator = std::function<void(const Vec3Array& v, Vec3Array& out)>;

class EquilibriumPreconditioner {
 public:
  virtual ~EquilibriumPreconditioner() = default;
  /// z = P^{-1} r on the free nodes (z is sized like r; prescribed entries zero). False when there is no
  /// usable factor (the solver then uses z = r).
  virtual bool apply(const Vec3Array& r, Vec3Array& z) const = 0;
  /// For summary.json: what P is and what it cost.
  virtual nlohmann::json info() const = 0;
  /// X = P^{-1} B on packed free-node vectors (several columns at once), for the contact correction
  /// (contact_correction.hpp). False when P cannot (then contacts are only filtered).
  virtual bool solve_columns(const Eigen::MatrixXd& /*B*/, Eigen::MatrixXd& /*X*/) const { return false; }
  /// Changes whenever P does (a refactorisation), unique over every preconditioner of the process, so cached
  /// products with P^{-1} can tell they are stale.
  virtual long long version() const { return 0; }
  /// A preconditioner that smooths with the Newton matrix itself (multigrid) gets it from the solver before
  /// each conjugate-gradient solve (null after it); the others ignore it.
  virtual void set_operator(const NewtonOperator* /*op*/) const {}
  /// A preconditioner with a part formed at one state (the wall multigrid's exact window round the tools)
  /// forms it again at x where that part no longer fits (the multigrid: other contact samples). The solver
  /// calls it before each Newton step's conjugate gradients whose state a step moved since the solve began
  /// (the caller prepared the first); the others ignore it.
  virtual void follow_state(const Vec3Array& /*x*/) {}
  /// True when apply() already respects the contacts' constraints (the solver then adds no contact
  /// correction).
  virtual bool handles_contacts() const { return false; }
};

/// P = a factor of the virtual tetrahedra's linear-elastic stiffness on the free nodes (exact sparse Cholesky
/// or incomplete Cholesky). Cheap to build, but a poor match for the meshless Hessian on thin walls (hundreds
/// of CG iterations per Newton step on the vein).
class TetStiffnessPreconditioner final : public EquilibriumPreconditioner {
 public:
  /// kind: "cholesky", "incomplete_cholesky" or "none".
  TetStiffnessPreconditioner(const Problem& problem, const FreeDofs& free, const std::string& kind);
  bool apply(const Vec3Array& r, Vec3Array& z) const override;
  nlohmann::json info() const override;

 private:
  const FreeDofs& free_;
  std::string kind_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> cholesky_;
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> incomplete_;
  bool ready_ = false;
};

}  // namespace vascsim
