#include "vascsim/rod/rod_statics.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vascsim::rod {

namespace {

// The free coordinates and the restriction of a vector or of the Hessian to them.
struct FreeSet {
  std::vector<Index> free;  // coordinate of each free unknown
  std::vector<Index> slot;  // per coordinate its free unknown, -1 when held
  explicit FreeSet(const std::vector<char>& held) : slot(held.size(), -1) {
    for (std::size_t k = 0; k < held.size(); ++k)
      if (!held[k]) {
        slot[k] = static_cast<Index>(free.size());
        free.push_back(static_cast<Index>(k));
      }
  }
  Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double>& H) const {
    std::vector<Eigen::Triplet<double>> t;
    for (int c = 0; c < H.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(H, c); it; ++it) {
        const Index r = slot[static_cast<std::size_t>(it.row())],
                    s = slot[static_cast<std::size_t>(it.col())];
        if (r >= 0 && s >= 0) t.emplace_back(r, s, it.value());
      }
    Eigen::SparseMatrix<double> out(static_cast<Index>(free.size()), static_cast<Index>(free.size()));
    out.setFromTriplets(t.begin(), t.end());
    return out;
  }
};

using Potentials = std::vector<const RodPotential*>;

double potential(const CosseratRod& rod, const Vec3Array& f, const Potentials& extra) {
  double p = rod.energy();
  for (const RodPotential* e : extra) p += e->energy(rod);
  for (std::size_t i = 0; i < f.size(); ++i) p -= f[i].dot(rod.positions()[i]);
  return p;
}

// The gradient of Pi (forces subtracted) in force units: the rotational components divided by the length.
Eigen::VectorXd scaled_gradient(const CosseratRod& rod, const Vec3Array& f, double length,
                                const Potentials& extra) {
  Eigen::VectorXd g = rod.gradient();
  for (const RodPotential* e : extra) e->add_gradient(rod, g);
  for (std::size_t i = 0; i < f.size(); ++i)
    g.segment<3>(CosseratRod::position_dof(static_cast<Index>(i))) -= f[i];
  g.tail(3 * rod.num_edges()) /= length;
  return g;
}

// The force an edge's strain is uncertain by when its ends are known to round-off of their coordinates: its
// stretch is a difference of positions |x| apart over an edge of length l, so EA 16 eps |x| / l (N). A stiff
// wire's axial stiffness makes this the floor of the residual: 1e-9 of a tip load that bends it by a radian
// for a 0.035-inch wire 50 mm from the origin in 1 mm edges.
double roundoff_n(const CosseratRod& rod) {
  double xmax = 0.0, lmin = std::numeric_limits<double>::infinity();
  for (const Vec3& x : rod.positions()) xmax = std::max(xmax, x.norm());
  const Vec3Array& rest = rod.rest_shape().nodes;
  for (std::size_t j = 0; j + 1 < rest.size(); ++j) lmin = std::min(lmin, (rest[j + 1] - rest[j]).norm());
  return 16.0 * std::numeric_limits<double>::epsilon() * rod.stiffness().shear_stretch_n.maxCoeff() * xmax /
         lmin;
}

Eigen::SparseMatrix<double> full_hessian(const CosseratRod& rod, const Potentials& extra) {
  Eigen::SparseMatrix<double> H = rod.hessian();
  if (extra.empty()) return H;
  std::vector<Eigen::Triplet<double>> t;
  for (const RodPotential* e : extra) e->add_hessian(rod, t);
  Eigen::SparseMatrix<double> C(H.rows(), H.cols());
  C.setFromTriplets(t.begin(), t.end());
  return H + C;
}

}  // namespace

RodStaticsReport solve_rod_statics(CosseratRod& rod, const std::vector<char>& held, const Vec3Array& forces,
                                   const RodStaticsOptions& options, const Potentials& potentials) {
  if (held.size() != static_cast<std::size_t>(rod.num_dofs()))
    throw std::invalid_argument("solve_rod_statics: one 'held' flag per generalised coordinate");
  if (!forces.empty() && forces.size() != static_cast<std::size_t>(rod.num_nodes()))
    throw std::invalid_argument("solve_rod_statics: one force per node");
  if (options.load_steps < 1 || options.max_newton_iterations < 1 || !(options.rel_tolerance > 0.0))
    throw std::invalid_argument("solve_rod_statics: load_steps, max_newton_iterations and rel_tolerance > 0");
  const FreeSet fs(held);
  const double L = rod.length();
  RodStaticsReport report;
  for (int step = 1; step <= options.load_steps; ++step) {
    Vec3Array f = forces;
    for (Vec3& v : f) v *= static_cast<double>(step) / options.load_steps;
    double fmax = 0.0;
    for (const Vec3& v : f) fmax = std::max(fmax, v.norm());
    report.converged = false;
    for (int it = 0; it <= options.max_newton_iterations; ++it) {
      // The rod's own forces and the other energies' apart: together with the loads they are the residual,
      // and each is a force level the residual is measured against (a rod turned only by its clamps, or held
      // by its contacts against a small load, has no other).
      Eigen::VectorXd g_elastic = rod.gradient(), g_others = Eigen::VectorXd::Zero(rod.num_dofs());
      for (const RodPotential* e : potentials) e->add_gradient(rod, g_others);
      g_elastic.tail(3 * rod.num_edges()) /= L;
      g_others.tail(3 * rod.num_edges()) /= L;
      Eigen::VectorXd g = g_elastic + g_others;
      for (std::size_t i = 0; i < f.size(); ++i)
        g.segment<3>(CosseratRod::position_dof(static_cast<Index>(i))) -= f[i];
      double reaction = 0.0, residual = 0.0, level = 0.0;
      for (std::size_t k = 0; k < held.size(); ++k) {
        const Index u = static_cast<Index>(k);
        double& v = held[k] ? reaction : residual;
        v = std::max(v, std::abs(g[u]));
        if (!held[k]) level = std::max({level, std::abs(g_elastic[u]), std::abs(g_others[u])});
      }
      const double scale = std::max({fmax, reaction, level, std::numeric_limits<double>::min()});
      report.relative_residual = residual / scale;
      if (residual <= options.rel_tolerance * scale + roundoff_n(rod)) {
        report.converged = true;
        break;
      }
      if (it == options.max_newton_iterations) break;
      ++report.newton_iterations;
      // The Newton step on the free coordinates (the unscaled gradient: the Hessian's units).
      const Eigen::VectorXd g_raw = [&] {
        Eigen::VectorXd r = g;
        r.tail(3 * rod.num_edges()) *= L;
        return r;
      }();
      Eigen::VectorXd gf(static_cast<Index>(fs.free.size()));
      for (std::size_t u = 0; u < fs.free.size(); ++u) gf[static_cast<Index>(u)] = g_raw[fs.free[u]];
      const Eigen::SparseMatrix<double> H = fs.restrict(full_hessian(rod, potentials));
      const double diag = H.diagonal().cwiseAbs().maxCoeff();
      Eigen::VectorXd df;
      for (double shift = 0.0;; shift = shift == 0.0 ? 1e-8 * diag : 10.0 * shift) {
        Eigen::SparseMatrix<double> A = H;
        if (shift > 0.0)
          for (Index k = 0; k < A.rows(); ++k) A.coeffRef(k, k) += shift;
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
        if (ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 0.0).all()) {
          df = ldlt.solve(-gf);
          break;
        }
        if (shift > 1e6 * diag) throw std::runtime_error("solve_rod_statics: no descent direction");
      }
      Eigen::VectorXd d = Eigen::VectorXd::Zero(rod.num_dofs());
      for (std::size_t u = 0; u < fs.free.size(); ++u) d[fs.free[u]] = df[static_cast<Index>(u)];
      // Backtracking on Pi (Armijo); where Pi's change is within its round-off (near equilibrium Pi's
      // decrease, of the order of the residual squared, drowns in the stiff edges' energy) a step that lowers
      // the residual is taken instead. (Taking any step that halves the residual, whatever Pi does, made the
      // contact solves of a wire in the aorta's arch cycle.)
      const double p0 = potential(rod, f, potentials), slope = gf.dot(df);
      const Vec3Array x0 = rod.positions();
      const std::vector<Quaternion> q0 = rod.frames();
      double alpha = 1.0;
      for (int k = 0; k < 40; ++k, alpha *= 0.5) {
        rod.set_configuration(x0, q0);
        rod.apply_increment(d, alpha);
        const double p = potential(rod, f, potentials);
        if (p <= p0 + 1e-4 * alpha * slope) break;
        if (std::abs(p - p0) > 1e-9 * std::abs(p0)) continue;  // a real increase: shorter
        double r = 0.0;
        const Eigen::VectorXd gt = scaled_gradient(rod, f, L, potentials);
        for (std::size_t u = 0; u < fs.free.size(); ++u) r = std::max(r, std::abs(gt[fs.free[u]]));
        if (r < residual) break;
      }
    }
    if (!report.converged) return report;
  }
  return report;
}

bool rod_is_stable(const CosseratRod& rod, const std::vector<char>& held, const Potentials& potentials) {
  if (held.size() != static_cast<std::size_t>(rod.num_dofs()))
    throw std::invalid_argument("rod_is_stable: one 'held' flag per generalised coordinate");
  const FreeSet fs(held);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(fs.restrict(full_hessian(rod, potentials)));
  return ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 0.0).all();
}

}  // namespace vascsim::rod
