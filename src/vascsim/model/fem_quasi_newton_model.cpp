#include "vascsim/model/fem_quasi_newton_model.hpp"

#include <spdlog/spdlog.h>
#include <cmath>
#include <limits>

#include "vascsim/model/tet_stiffness.hpp"

namespace vascsim {

namespace {

constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 30;

}  // namespace

FemQuasiNewtonSettings read_fem_quasi_newton_settings(JsonReader& b) {
  FemQuasiNewtonSettings s;
  s.frames = read_baseline_frames(b);
  s.history = b.integer("history", 6, 1, 100);
  s.max_iterations = b.integer("max_iterations", 20, 1, 100000);
  s.rel_tolerance = b.number("rel_tolerance", 1e-6, 1e-14, 0.5);
  s.damping_per_s = b.number("damping_per_s", 0.0, 0.0, 1e7);
  b.finish();
  return s;
}

ModelEntry fem_quasi_newton_model_entry() {
  return make_baseline_entry<FemQuasiNewtonModel, FemQuasiNewtonSettings>(
      "fem_quasi_newton",
      "baseline [23] Liu & Yao 2018 (interpretation): implicit neo-Hookean tet FEM by L-BFGS with a "
      "prefactored "
      "initial Hessian",
      &read_fem_quasi_newton_settings);
}

FemQuasiNewtonModel::FemQuasiNewtonModel(const Problem& problem, const FemQuasiNewtonSettings& settings)
    : DynamicBaseline(problem, "fem_quasi_newton", settings.frames),
      settings_(settings),
      free_(problem),
      contacts_(problem, free_) {
  const Discretization& disc = problem.discretization();
  const Vec3Array& X = disc.rest_positions();
  lambda_ = disc.material().lame_lambda();
  mu_ = disc.material().shear_modulus();
  mass_ = disc.masses();
  for (const Tet& t : disc.tets()) {
    Mat3 Dm;
    for (int c = 0; c < 3; ++c) Dm.col(c) = X[t[c + 1]] - X[t[0]];
    dm_inv_.push_back(Dm.inverse());
    rest_volume_.push_back(Dm.determinant() / 6.0);
  }
  // The initial Hessian M/h^2 + K_0 on the free dofs, factored once.
  const Eigen::SparseMatrix<double> K = linear_tet_stiffness(X, disc.tets(), lambda_, mu_);
  std::vector<Eigen::Triplet<double>> trip;
  for (Eigen::Index c = 0; c < K.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) {
      const Index a = free_.slot[static_cast<std::size_t>(it.row() / 3)],
                  b = free_.slot[static_cast<std::size_t>(c / 3)];
      if (a >= 0 && b >= 0) trip.emplace_back(3 * a + it.row() % 3, 3 * b + c % 3, it.value());
    }
  for (std::size_t a = 0; a < free_.nodes.size(); ++a)
    for (int c = 0; c < 3; ++c) trip.emplace_back(3 * a + c, 3 * a + c, mass_[free_.nodes[a]] / (h_ * h_));
  Eigen::SparseMatrix<double> H(free_.size(), free_.size());
  H.setFromTriplets(trip.begin(), trip.end());
  H.makeCompressed();
  factor_ = std::make_unique<SparseCholesky>();
  if (free_.size() > 0) factor_->compute(H);
  spdlog::info("fem_quasi_newton: {} tets, {} free dofs, initial Hessian factored ({:.3g} s)", dm_inv_.size(),
               free_.size(), factor_->stats().factorize_s);
}

FemQuasiNewtonModel::~FemQuasiNewtonModel() = default;

double FemQuasiNewtonModel::elastic_energy(const Vec3Array& x, Vec3Array* grad) const {
  const auto& tets = problem_.discretization().tets();
  if (grad) grad->assign(x.size(), Vec3::Zero());
  double U = 0.0;
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& T = tets[t];
    Mat3 Ds;
    for (int c = 0; c < 3; ++c) Ds.col(c) = x[T[c + 1]] - x[T[0]];
    const Mat3 F = Ds * dm_inv_[t];
    const double J = F.determinant();
    if (!(J > 0.0)) return std::numeric_limits<double>::infinity();
    const double lnJ = std::log(J);
    U += rest_volume_[t] *
         (0.5 * mu_ * ((F.transpose() * F).trace() - 3.0) - mu_ * lnJ + 0.5 * lambda_ * lnJ * lnJ);
    if (!grad) continue;
    const Mat3 FinvT = F.inverse().transpose();
    const Mat3 P = mu_ * (F - FinvT) + lambda_ * lnJ * FinvT;
    const Mat3 G = rest_volume_[t] * P * dm_inv_[t].transpose();  // dU/dx_{1..3} as columns
    for (int c = 0; c < 3; ++c) {
      (*grad)[T[c + 1]] += G.col(c);
      (*grad)[T[0]] -= G.col(c);
    }
  }
  return U;
}

double FemQuasiNewtonModel::objective(const Vec3Array& x, Vec3Array& grad) const {
  double g = elastic_energy(x, &grad);
  if (!std::isfinite(g)) return g;
  const double inv_h2 = 1.0 / (h_ * h_);
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (problem_.constrained()[i]) continue;
    const Vec3 d = x[i] - y_[i];
    g += 0.5 * mass_[i] * inv_h2 * d.squaredNorm() - f_ext_[i].dot(x[i]);
    grad[i] += mass_[i] * inv_h2 * d - f_ext_[i];
  }
  return g;
}

void FemQuasiNewtonModel::direction(const Vec3Array& grad, Vec3Array& d) {
  // L-BFGS two-loop recursion (Nocedal & Wright, Algorithm 7.4) with H_0^{-1} = (M/h^2 + K_0)^{-1}.
  Vec3Array q = grad;
  filter_free(q, contacts_);
  std::vector<double> alpha(pairs_.size());
  for (std::size_t k = pairs_.size(); k-- > 0;) {
    const auto& [s, y] = pairs_[k];
    alpha[k] = dot(s, q) / dot(y, s);
    for (std::size_t i = 0; i < q.size(); ++i) q[i] -= alpha[k] * y[i];
  }
  Eigen::VectorXd packed, solved;
  free_.pack(q, packed);
  if (packed.size() > 0) factor_->solve(packed, solved);
  d.assign(q.size(), Vec3::Zero());
  free_.unpack(solved, d);
  filter_free(d, contacts_);
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const auto& [s, y] = pairs_[k];
    const double beta = dot(y, d) / dot(y, s);
    for (std::size_t i = 0; i < d.size(); ++i) d[i] += (alpha[k] - beta) * s[i];
  }
  for (auto& v : d) v = -v;
}

int FemQuasiNewtonModel::minimise(Vec3Array& x, Vec3Array& grad, double& g, double tolerance) {
  auto filtered = [&](const Vec3Array& v) {
    Vec3Array f = v;
    filter_free(f, contacts_);
    return f;
  };
  Vec3Array gf = filtered(grad), d, trial, trial_grad;
  int it = 0;
  for (; it < settings_.max_iterations && std::sqrt(dot(gf, gf)) > tolerance; ++it) {
    direction(grad, d);
    double slope = dot(gf, d);
    if (!(slope < 0.0)) {  // not a descent direction: restart from H_0
      pairs_.clear();
      direction(grad, d);
      slope = dot(gf, d);
    }
    double step = 1.0, g_trial = g;
    for (int k = 0; k < kMaxHalvings; ++k, step *= 0.5) {
      trial = x;
      for (std::size_t i = 0; i < x.size(); ++i) trial[i] += step * d[i];
      contacts_.project(trial, false);
      g_trial = objective(trial, trial_grad);
      if (g_trial <= g + kArmijo * step * slope) break;
    }
    if (!(g_trial <= g + kArmijo * step * slope)) break;  // no decrease: the tolerance is below round-off
    Vec3Array gf_trial = filtered(trial_grad), s(x.size()), y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) s[i] = trial[i] - x[i], y[i] = gf_trial[i] - gf[i];
    if (dot(s, y) > 0.0) {
      pairs_.emplace_back(std::move(s), std::move(y));
      if (static_cast<int>(pairs_.size()) > settings_.history) pairs_.pop_front();
    }
    x.swap(trial);
    grad.swap(trial_grad);
    gf.swap(gf_trial);
    g = g_trial;
  }
  last_reduction_ = std::sqrt(dot(gf, gf));
  return it;
}

StepReport FemQuasiNewtonModel::frame(double /*s_prev*/, double s) {
  const std::size_t n = x_.size();
  for (std::size_t o = 0; o < tools_.size(); ++o) contacts_.place(o, tools_.geometry(o, s));
  problem_.external_forces(s, f_ext_);
  y_.resize(n);
  for (std::size_t i = 0; i < n; ++i) y_[i] = x_[i] + h_ * v_[i];
  Vec3Array x = y_, grad;
  problem_.apply_constraints(s, x);
  contacts_.project(x, true);
  pairs_.clear();
  double g = objective(x, grad);
  Vec3Array gf = grad;
  filter_free(gf, contacts_);
  const double tolerance = settings_.rel_tolerance * std::sqrt(dot(gf, gf));
  StepReport rep;
  for (int round = 0; round < 4; ++round) {
    rep.iterations += minimise(x, grad, g, tolerance);
    Vec3Array r = grad;
    for (auto& v : r) v = -v;
    const int added = contacts_.project(x, true);
    const int released = contacts_.empty() ? 0 : contacts_.release_pulling(r);
    if (added == 0 && released == 0) break;
    pairs_.clear();
    g = objective(x, grad);
  }
  iterations_total_ += rep.iterations;
  rep.converged = last_reduction_ <= tolerance;
  if (!contacts_.empty()) {
    Vec3Array r = grad;
    for (auto& v : r) v = -v;
    loads_ = contacts_.loads(r, x, tools_.points(s));
  }
  const double decay = std::exp(-settings_.damping_per_s * h_);
  for (std::size_t i = 0; i < n; ++i) v_[i] = (x[i] - x_[i]) * (decay / h_);
  x_.swap(x);
  elastic_energy(x_, &f_int_);
  for (auto& f : f_int_) f = -f;
  return rep;
}

nlohmann::json FemQuasiNewtonModel::method_info() const {
  return {{"method",
           "implicit neo-Hookean tet FEM, L-BFGS with prefactored M/h^2 + K_0 (interpretation of Liu & Yao "
           "2018, [23], after Liu, Bouaziz, Kavan 2017)"},
          {"interpretation", true},
          {"tets", dm_inv_.size()},
          {"lame_lambda_pa", lambda_},
          {"shear_modulus_pa", mu_},
          {"history", settings_.history},
          {"max_iterations", settings_.max_iterations},
          {"rel_tolerance", settings_.rel_tolerance},
          {"lbfgs_iterations_total", iterations_total_},
          {"factor_nnz", factor_->stats().nnz_l}};
}

}  // namespace vascsim
