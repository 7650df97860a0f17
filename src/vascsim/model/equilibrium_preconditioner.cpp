#include "vascsim/model/equilibrium_preconditioner.hpp"

#include <spdlog/spdlog.h>

#include "vascsim/core/error.hpp"
#include "vascsim/model/tet_stiffness.hpp"

namespace vascsim {

TetStiffnessPreconditioner::TetStiffnessPreconditioner(const Problem& problem, const FreeDofs& free,
                                                       const std::string& kind)
    : free_(free), kind_(kind) {
  if (kind != "incomplete_cholesky" && kind != "cholesky" && kind != "none")
    throw InputError("quasi_static: the tet preconditioner must be cholesky, incomplete_cholesky or none");
  const auto& disc = problem.discretization();
  const auto& E = problem.energy();
  const Eigen::SparseMatrix<double> K =
      linear_tet_stiffness(disc.rest_positions(), disc.tets(),
                           E.strain_lambda() + E.options().volume_stiffness_pa, E.shear_modulus());
  std::vector<Eigen::Triplet<double>> trip;
  for (int c = 0; c < K.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) {
      const Eigen::Index a = free.slot[it.row() / 3], b = free.slot[it.col() / 3];
      if (a >= 0 && b >= 0) trip.emplace_back(3 * a + it.row() % 3, 3 * b + it.col() % 3, it.value());
    }
  const Eigen::Index nf = free.size();
  Eigen::SparseMatrix<double> Kff(nf, nf);
  Kff.setFromTriplets(trip.begin(), trip.end());
  if (nf > 0 && kind == "cholesky") {
    cholesky_.compute(Kff);
    ready_ = cholesky_.info() == Eigen::Success && (cholesky_.vectorD().array() > 0.0).all();
  } else if (nf > 0 && kind == "incomplete_cholesky") {
    incomplete_.compute(Kff);
    ready_ = incomplete_.info() == Eigen::Success;
  }
  if (nf > 0 && kind != "none" && !ready_)
    spdlog::warn(
        "quasi_static: the tetrahedral preconditioner is singular (is every part of the body "
        "supported?); using no preconditioner");
}

bool TetStiffnessPreconditioner::apply(const Vec3Array& r, Vec3Array& z) const {
  if (!ready_) return false;
  Eigen::VectorXd b;
  free_.pack(r, b);
  const Eigen::VectorXd y =
      kind_ == "cholesky" ? Eigen::VectorXd(cholesky_.solve(b)) : Eigen::VectorXd(incomplete_.solve(b));
  z.assign(r.size(), Vec3::Zero());
  free_.unpack(y, z);
  return true;
}

nlohmann::json TetStiffnessPreconditioner::info() const {
  return ready_ ? kind_ + " of the tet linear stiffness" : std::string("none");
}

}  // namespace vascsim
