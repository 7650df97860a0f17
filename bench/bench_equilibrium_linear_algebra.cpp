// Which matrix should the sparse Cholesky preconditioner of the equilibrium solves factor? Measured on the
// vein-indent scene (20 mm vein, 0.3 mm wall, clamped ends, bonded outer patch pushed 1.2 mm) at several node
// spacings, for three candidate matrices, each without and with the backward-Euler mass shift M/dt^2
// (dt = 1 ms):
//   tet      the linear-elastic P1 stiffness of the virtual tetrahedra (today's quasi_static preconditioner)
//   compact  the meshless Hessian on the stencil pairs only, dropped blocks lumped (model/energy_hessian.hpp)
//   full     the exact meshless Hessian (every pair of nodes within 2h)
// For each: assembly (symbolic once, numeric refill), CHOLMOD analyse / factorize / one solve, nnz(L), and
// the PCG iterations to a relative residual 1e-6 (true operator: the matrix-free hessian_product, plus the
// same mass shift) on
//   (a)  the first linear system of the first load step from rest: K(X)_ff dx = -K(X)_fc dp (dp: the
//        prescribed increment of load step 1 of 12), the system quasi_static's linear predictor solves;
//   (a1) the first Newton system after that predictor: K(x1)_ff dx = r(x1) (0.1 mm push);
//   (b)  the drifted case: the factor built at rest, used at the state of the full 1.2 mm push (from
//        quasi_static to s = 1), right-hand side -K(x)_fc dp for one more load increment;
//   (c)  as (b) with the preconditioner refactored at that state (PSD-projected tangents).
// Also: one hessian_product, the CHOLMOD orderings, and the refill on 1 vs 2 OpenMP threads.
//
// Run (Release build), e.g.:
//   OMP_NUM_THREADS=1 nice build/bench/bench_equilibrium_linear_algebra --spacings
//   0.35e-3,0.3e-3,0.2e-3,0.15e-3
// The deformed states are cached in --cache (default: bench-cache/ in the working folder).

#include <omp.h>
#include <spdlog/spdlog.h>

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "vascsim/core/blas_control.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/sparse_cholesky.hpp"
#include "vascsim/model/energy_hessian.hpp"
#include "vascsim/model/quasi_static_model.hpp"
#include "vascsim/model/tet_stiffness.hpp"
#include "vascsim/run/simulation.hpp"

namespace {

using namespace vascsim;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? NAN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Median wall time of `repeats` calls, s.
double time_median(int repeats, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    f();
    t.push_back(seconds_since(t0));
  }
  return median(t);
}

struct Args {
  std::string scene = std::string(VASCSIM_SOURCE_DIR) + "/scenes/vein-indent.json";
  std::vector<double> spacings{0.35e-3, 0.3e-3, 0.2e-3, 0.15e-3};
  int repeats = 3;
  Index drift_max_nodes = 30000;  // run quasi_static for (b) only up to this many nodes
  std::string cache = "bench-cache";
  bool orderings = true;
  bool threads = true;
  double dt = 1e-3;  // s
  double tol = 1e-6;
  int max_iterations = 5000;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + k);
      return argv[++i];
    };
    if (k == "--scene")
      a.scene = next();
    else if (k == "--spacings") {
      a.spacings.clear();
      std::stringstream ss(next());
      for (std::string t; std::getline(ss, t, ',');) a.spacings.push_back(std::stod(t));
    } else if (k == "--repeats")
      a.repeats = std::stoi(next());
    else if (k == "--drift-max-nodes")
      a.drift_max_nodes = std::stoi(next());
    else if (k == "--cache")
      a.cache = next();
    else if (k == "--no-orderings")
      a.orderings = false;
    else if (k == "--no-threads")
      a.threads = false;
    else if (k == "--max-iterations")
      a.max_iterations = std::stoi(next());
    else
      throw std::invalid_argument("unknown argument " + k);
  }
  return a;
}

// The reduced (free-node) vectors and the true operator K(x)_ff + shift, matrix-free.
class Reduced {
 public:
  Reduced(const Problem& p) : p_(p) {
    const Index n = p.discretization().num_nodes();
    slot_.assign(static_cast<std::size_t>(n), -1);
    for (Index i = 0; i < n; ++i)
      if (!p.constrained()[static_cast<std::size_t>(i)]) {
        slot_[static_cast<std::size_t>(i)] = static_cast<Index>(free_.size());
        free_.push_back(i);
      }
    full_.assign(static_cast<std::size_t>(n), Vec3::Zero());
  }
  const std::vector<Index>& slot() const { return slot_; }
  Eigen::Index size() const { return 3 * static_cast<Eigen::Index>(free_.size()); }
  Eigen::VectorXd gather(const Vec3Array& v) const {
    Eigen::VectorXd out(size());
    for (std::size_t a = 0; a < free_.size(); ++a)
      out.segment<3>(3 * static_cast<Eigen::Index>(a)) = v[static_cast<std::size_t>(free_[a])];
    return out;
  }
  void scatter(const Eigen::VectorXd& v, Vec3Array& out) const {
    out.assign(p_.discretization().rest_positions().size(), Vec3::Zero());
    for (std::size_t a = 0; a < free_.size(); ++a)
      out[static_cast<std::size_t>(free_[a])] = v.segment<3>(3 * static_cast<Eigen::Index>(a));
  }
  // out = (K(lin) v)_f + shift .* v
  void apply(const PointPrimitiveEnergy::Linearization& lin, const Eigen::VectorXd& shift,
             const Eigen::VectorXd& v, Eigen::VectorXd& out) {
    scatter(v, full_);
    p_.energy().hessian_product(lin, full_, Kv_);
    out = gather(Kv_);
    if (shift.size()) out += shift.cwiseProduct(v);
  }

 private:
  const Problem& p_;
  std::vector<Index> slot_;
  std::vector<Index> free_;
  Vec3Array full_, Kv_;
};

struct PcgResult {
  int iterations = 0;
  bool converged = false;
  bool negative_curvature = false;
  double seconds = 0.0;
};

PcgResult pcg(Reduced& red, const PointPrimitiveEnergy::Linearization& lin, const Eigen::VectorXd& shift,
              SparseCholesky& pre, const Eigen::VectorXd& b, double tol, int max_it,
              Eigen::VectorXd* solution = nullptr) {
  const auto t0 = Clock::now();
  PcgResult res;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size()), r = b, z, p, Ap;
  pre.solve(r, z);
  p = z;
  double rz = r.dot(z);
  const double target = tol * b.norm();
  for (int it = 0; it < max_it; ++it) {
    red.apply(lin, shift, p, Ap);
    const double pAp = p.dot(Ap);
    if (!(pAp > 0.0)) {
      res.negative_curvature = true;
      res.iterations = it;
      break;
    }
    const double alpha = rz / pAp;
    x += alpha * p;
    r -= alpha * Ap;
    res.iterations = it + 1;
    if (r.norm() <= target) {
      res.converged = true;
      break;
    }
    pre.solve(r, z);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  res.seconds = seconds_since(t0);
  if (solution) *solution = x;
  return res;
}

std::string fmt_pcg(const PcgResult& r) {
  if (r.iterations == 0 && !r.converged && !r.negative_curvature) return "-";
  return fmt::format("{}{}", r.iterations,
                     r.negative_curvature ? " (neg. curv.)"
                     : r.converged        ? ""
                                          : " (no conv.)");
}

// The drifted state: quasi_static to s = 1, cached.
struct Drift {
  Vec3Array x;
  bool available = false;
  double quasi_static_s = NAN;  // wall time of the run (NaN: from the cache)
  long long newton = -1, cg = -1;
};

Drift drifted_state(Simulation& sim, const std::string& cache_file) {
  Drift d;
  const std::size_t n = sim.discretization().rest_positions().size();
  if (std::ifstream in(cache_file, std::ios::binary); in) {
    std::uint64_t m = 0;
    in.read(reinterpret_cast<char*>(&m), sizeof(m));
    if (m == n) {
      d.x.resize(n);
      in.read(reinterpret_cast<char*>(d.x.data()), static_cast<std::streamsize>(n * sizeof(Vec3)));
      d.available = static_cast<bool>(in);
      if (d.available) return d;
    }
  }
  const auto t0 = Clock::now();
  for (int k = 1; k <= sim.model().num_steps(); ++k) sim.advance(k);
  d.quasi_static_s = seconds_since(t0);
  const auto info = sim.model().info();
  d.newton = info.value("newton_iterations", -1LL);
  d.cg = info.value("cg_iterations", -1LL);
  d.x = sim.model().positions();
  d.available = true;
  std::filesystem::create_directories(std::filesystem::path(cache_file).parent_path());
  std::ofstream out(cache_file, std::ios::binary);
  const std::uint64_t m = n;
  out.write(reinterpret_cast<const char*>(&m), sizeof(m));
  out.write(reinterpret_cast<const char*>(d.x.data()), static_cast<std::streamsize>(n * sizeof(Vec3)));
  return d;
}

// The tet stiffness restricted to the free nodes, lower triangle, plus the shift (N/m per dof).
Eigen::SparseMatrix<double> tet_matrix(const Problem& p, const std::vector<Index>& slot,
                                       const Eigen::VectorXd& shift) {
  const auto& disc = p.discretization();
  const auto& E = p.energy();
  // As quasi_static: lambda of the strain term plus k_v (the small-strain lambda of the energy).
  const Eigen::SparseMatrix<double> K =
      linear_tet_stiffness(disc.rest_positions(), disc.tets(),
                           E.strain_lambda() + E.options().volume_stiffness_pa, E.shear_modulus());
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(K.nonZeros()) / 2 + static_cast<std::size_t>(shift.size()));
  for (int c = 0; c < K.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) {
      const Index a = slot[static_cast<std::size_t>(it.row() / 3)],
                  b = slot[static_cast<std::size_t>(it.col() / 3)];
      if (a < 0 || b < 0) continue;
      const Eigen::Index r = 3 * a + it.row() % 3, cc = 3 * b + it.col() % 3;
      if (r >= cc) trip.emplace_back(r, cc, it.value());
    }
  for (Eigen::Index i = 0; i < shift.size(); ++i) trip.emplace_back(i, i, shift[i]);
  Eigen::SparseMatrix<double> A(shift.size(), shift.size());
  A.setFromTriplets(trip.begin(), trip.end());
  return A;
}

struct Row {
  double spacing_m = 0;
  Index nodes = 0, free_nodes = 0;
  std::string candidate;
  bool shifted = false;
  double nnz_a = 0, nnz_l = 0, stored_l = 0, flops = 0;
  std::string ordering;
  double symbolic_ms = NAN, assemble_ms = NAN, assemble_psd_ms = NAN, analyse_ms = NAN, factor_ms = NAN,
         solve_ms = NAN, solve32_ms = NAN;
  PcgResult a, a1, b, c;
  std::string failure;
};

void print_row(const Row& r) {
  fmt::print(
      "| {:>6} | {:<8} | {:>5} | {:>9.3g} | {:>9.3g} | {:>8} | {:>7.1f} | {:>7.1f} | {:>7.1f} | {:>8.1f} | "
      "{:>8.1f} | {:>7.2f} | "
      "{:>7.2f} | {:>6} | {:>6} | {:>12} | {:>9.0f} | {:>12} | {:>9.0f} | {:>6.0f} |{}\n",
      r.nodes, r.candidate, r.shifted ? "M/h2" : "-", r.nnz_a, r.nnz_l, r.ordering, r.symbolic_ms,
      r.assemble_ms, r.assemble_psd_ms, r.analyse_ms, r.factor_ms, r.solve_ms, r.solve32_ms, fmt_pcg(r.a),
      fmt_pcg(r.a1), fmt_pcg(r.b), r.b.seconds * 1e3, fmt_pcg(r.c), r.c.seconds * 1e3, r.stored_l * 8e-6,
      r.failure.empty() ? "" : " " + r.failure);
  std::fflush(stdout);
}

void print_header() {
  fmt::print(
      "| nodes  | cand.    | shift | nnz(A)    | nnz(L)    | ordering | sym ms  | asm ms  | asm+psd | "
      "analyse  | factor   | solve   "
      "| solve32 | it(a)  | it(a1) | it(b)        | pcg(b) ms | it(c)        | pcg(c) ms | L MB   |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
}

// What every candidate preconditioner of one resolution is measured with: the problem, the mass shift and the
// right-hand sides of the three situations (a) at rest, (a1) after the exact predictor, (b) drifted.
struct SizeCase {
  const Args& args;
  double spacing;
  const Problem& problem;
  const PointPrimitiveEnergy& energy;
  const Vec3Array& X;
  Reduced red;
  Index n = 0;
  Eigen::Index dim = 0;
  std::vector<double> shift_node;  // M/dt^2 per node, N/m (EnergyHessian)
  Eigen::VectorXd shift;           // the same per free dof
  Eigen::VectorXd b_a, b_a1, b_b;
  PointPrimitiveEnergy::Linearization lin_rest, lin_a1, lin_drift;
  Drift drift;

  SizeCase(const Args& a, double h, const Simulation& sim)
      : args(a),
        spacing(h),
        problem(sim.problem()),
        energy(sim.energy()),
        X(sim.discretization().rest_positions()),
        red(sim.problem()),
        n(sim.discretization().num_nodes()),
        dim(red.size()) {}
  std::size_t at(Index i) const { return static_cast<std::size_t>(i); }
};

void set_mass_shift(SizeCase& c, const Discretization& disc) {
  c.shift_node.resize(c.at(c.n));
  for (Index i = 0; i < c.n; ++i) c.shift_node[c.at(i)] = disc.masses()[c.at(i)] / (c.args.dt * c.args.dt);
  c.shift.resize(c.dim);
  for (Index i = 0; i < c.n; ++i)
    if (c.red.slot()[c.at(i)] >= 0)
      c.shift.segment<3>(3 * c.red.slot()[c.at(i)]).setConstant(c.shift_node[c.at(i)]);
}

// Reference: one Hessian-vector product at rest (with and without the per-state linearisation).
void print_hessian_product_time(const SizeCase& c) {
  Vec3Array v(c.at(c.n), Vec3(1e-6, -2e-6, 0.5e-6)), out;
  const auto lin = c.energy.linearize(c.X);
  const double hv_lin =
      time_median(std::max(c.args.repeats, 11), [&] { c.energy.hessian_product(lin, v, out); });
  const double hv_full =
      time_median(std::max(c.args.repeats, 11), [&] { c.energy.hessian_product(c.X, v, out); });
  fmt::print(
      "hessian_product: {:.2f} ms with a stored linearisation (per CG iteration), {:.2f} ms including it\n",
      hv_lin * 1e3, hv_full * 1e3);
}

// (a) at rest: rhs = -(K dp)_f, dp the prescribed increment of load step 1 (s1 = 1/steps); returns dp.
Vec3Array set_rest_case(SizeCase& c, double s1) {
  Vec3Array dp(c.at(c.n), Vec3::Zero()), Kdp;
  for (Index i = 0; i < c.n; ++i)
    if (c.problem.constrained()[c.at(i)]) dp[c.at(i)] = c.problem.prescribed_position(i, s1) - c.X[c.at(i)];
  c.energy.hessian_product(c.X, dp, Kdp);
  c.b_a = -c.red.gather(Kdp);
  c.lin_rest = c.energy.linearize(c.X);
  return dp;
}

// (b) drifted: quasi_static to s = 1 (cached), rhs = -(K(x) dp)_f for one more increment.
void set_drifted_case(SizeCase& c, const Scene& scene, double s1) {
  if (c.n > c.args.drift_max_nodes) {
    fmt::print("drifted case (b), (c) skipped at this size (--drift-max-nodes {})\n", c.args.drift_max_nodes);
    return;
  }
  const std::string file = fmt::format("{}/vein-indent-{:.3g}mm-{}.bin", c.args.cache, c.spacing * 1e3, c.n);
  Simulation qs(scene);  // a fresh model for the run
  c.drift = drifted_state(qs, file);
  if (!std::isnan(c.drift.quasi_static_s))
    fmt::print(
        "quasi_static to s = 1 (tet preconditioner, its default): {:.1f} s, {} Newton, {} CG iterations\n",
        c.drift.quasi_static_s, c.drift.newton, c.drift.cg);
  if (!c.drift.available) return;
  Vec3Array dp2(c.at(c.n), Vec3::Zero()), K2;
  for (Index i = 0; i < c.n; ++i)
    if (c.problem.constrained()[c.at(i)])
      dp2[c.at(i)] = c.problem.prescribed_position(i, 1.0 + s1) - c.problem.prescribed_position(i, 1.0);
  c.energy.hessian_product(c.drift.x, dp2, K2);
  c.b_b = -c.red.gather(K2);
  c.lin_drift = c.energy.linearize(c.drift.x);
  double umax = 0.0;
  for (Index i = 0; i < c.n; ++i) umax = std::max(umax, (c.drift.x[c.at(i)] - c.X[c.at(i)]).norm());
  fmt::print("drifted state: max displacement {:.3f} mm\n", umax * 1e3);
}

// (a1): x1 = X + dp + dx with dx the exact predictor (K(X)_ff dx = b_a, full Hessian factor), rhs = r(x1)_f.
void set_predictor_case(SizeCase& c, const Vec3Array& dp, double s1) {
  EnergyHessian H(c.energy, {HessianStencil::Full, false, true, CompactLumping::Polar}, c.red.slot());
  H.assemble(c.X);
  SparseCholesky chol;
  chol.compute(H.matrix());
  Eigen::VectorXd dx;
  chol.solve(c.b_a, dx);
  Vec3Array x1 = c.X, dxn;
  c.red.scatter(dx, dxn);
  for (Index i = 0; i < c.n; ++i) x1[c.at(i)] += dp[c.at(i)] + dxn[c.at(i)];
  Vec3Array f_int, f_ext;
  c.energy.forces(x1, f_int);
  c.problem.external_forces(s1, f_ext);
  for (Index i = 0; i < c.n; ++i) f_int[c.at(i)] += f_ext[c.at(i)];
  c.b_a1 = c.red.gather(f_int);
  c.lin_a1 = c.energy.linearize(x1);
}

struct Candidate {
  std::string name;
  HessianStencil stencil;
  CompactLumping lumping;
};

// The candidate's matrix at rest: assembly times into r; A_tet or H holds it.
const Eigen::SparseMatrix<double>* assemble_candidate(const SizeCase& c, const Candidate& cd, bool shifted,
                                                      Row& r, Eigen::SparseMatrix<double>& A_tet,
                                                      std::unique_ptr<EnergyHessian>& H) {
  const std::vector<double> sh_node = shifted ? c.shift_node : std::vector<double>{};
  if (cd.name == "tet") {
    r.assemble_ms =
        1e3 * time_median(c.args.repeats, [&] {
          A_tet = tet_matrix(c.problem, c.red.slot(), shifted ? c.shift : Eigen::VectorXd::Zero(c.dim));
        });
    return &A_tet;
  }
  auto t0 = Clock::now();
  H = std::make_unique<EnergyHessian>(c.energy, EnergyHessianOptions{cd.stencil, true, true, cd.lumping},
                                      c.red.slot());
  r.symbolic_ms = 1e3 * seconds_since(t0);
  r.assemble_psd_ms = 1e3 * time_median(c.args.repeats, [&] { H->assemble(c.X, sh_node); });
  // The exact refill (no projection) on a second object of the same pattern.
  EnergyHessian exact(c.energy, EnergyHessianOptions{cd.stencil, false, true, cd.lumping}, c.red.slot());
  r.assemble_ms = 1e3 * time_median(c.args.repeats, [&] { exact.assemble(c.X, sh_node); });
  return &H->matrix();
}

// One row of the table: a candidate matrix (with or without the mass shift) as the preconditioner of the
// three situations, and for the meshless candidates (c): refactored at the drifted state.
Row measure_candidate(SizeCase& c, const Candidate& cd, bool shifted) {
  Row r;
  r.spacing_m = c.spacing;
  r.nodes = c.n;
  r.free_nodes = static_cast<Index>(c.dim / 3);
  r.candidate = cd.name;
  r.shifted = shifted;
  const Eigen::VectorXd no_shift;
  const Eigen::VectorXd& sh = shifted ? c.shift : no_shift;
  Eigen::SparseMatrix<double> A_tet;
  std::unique_ptr<EnergyHessian> H;
  const Eigen::SparseMatrix<double>* A = assemble_candidate(c, cd, shifted, r, A_tet, H);
  // Single right-hand sides through the float copy of the factor (what the preconditioners use; the PCG
  // columns below run with it); one column as a matrix goes through CHOLMOD's double solve.
  SparseCholesky chol(SparseCholeskyOptions{CholeskyOrdering::Default, true, true});
  try {
    r.analyse_ms = 1e3 * time_median(c.args.repeats, [&] { chol.analyse(*A); });
    r.factor_ms = 1e3 * time_median(c.args.repeats, [&] { chol.factorize(*A); });
  } catch (const NumericalError& e) {
    r.failure = e.what();
    return r;
  }
  r.nnz_a = chol.stats().nnz_a;
  r.nnz_l = chol.stats().nnz_l;
  r.stored_l = chol.stats().stored_l;
  r.flops = chol.stats().flops;
  r.ordering = chol.stats().ordering;
  {
    Eigen::VectorXd z;
    Eigen::MatrixXd Z;
    const Eigen::MatrixXd B = c.b_a;
    r.solve_ms = 1e3 * time_median(std::max(c.args.repeats, 5), [&] { chol.solve(B, Z); });
    r.solve32_ms = 1e3 * time_median(std::max(c.args.repeats, 5), [&] { chol.solve(c.b_a, z); });
  }
  const Args& a = c.args;
  r.a = pcg(c.red, c.lin_rest, sh, chol, c.b_a, a.tol, a.max_iterations);
  r.a1 = pcg(c.red, c.lin_a1, sh, chol, c.b_a1, a.tol, a.max_iterations);
  if (!c.drift.available) return r;
  r.b = pcg(c.red, c.lin_drift, sh, chol, c.b_b, a.tol, a.max_iterations);
  if (!H) return r;
  H->assemble(c.drift.x,
              shifted ? c.shift_node : std::vector<double>{});  // PSD-projected refill, drifted state
  try {
    chol.factorize(H->matrix());
    r.c = pcg(c.red, c.lin_drift, sh, chol, c.b_b, a.tol, a.max_iterations);
  } catch (const NumericalError& e) {
    r.failure = std::string("(c): ") + e.what();
  }
  return r;
}

// CHOLMOD's orderings on the matrices at rest (no shift): nnz(L), analyse and factorize times.
void compare_orderings(const SizeCase& c) {
  fmt::print("\nCHOLMOD orderings (no shift, matrix at rest): nnz(L), analyse ms, factorize ms\n");
  fmt::print(
      "| nodes | cand. | ordering | nnz(L) | flops | analyse ms | factor ms "
      "|\n|---|---|---|---|---|---|---|\n");
  for (const std::string cand : {"tet", "compact", "full"}) {
    Eigen::SparseMatrix<double> A_tet;
    std::unique_ptr<EnergyHessian> H;
    const Eigen::SparseMatrix<double>* A = nullptr;
    if (cand == "tet") {
      A_tet = tet_matrix(c.problem, c.red.slot(), Eigen::VectorXd::Zero(c.dim));
      A = &A_tet;
    } else {
      const HessianStencil stencil = cand == "full" ? HessianStencil::Full : HessianStencil::Compact;
      H = std::make_unique<EnergyHessian>(
          c.energy, EnergyHessianOptions{stencil, false, true, CompactLumping::Polar}, c.red.slot());
      H->assemble(c.X);
      A = &H->matrix();
    }
    for (CholeskyOrdering o : {CholeskyOrdering::Default, CholeskyOrdering::Amd, CholeskyOrdering::Metis,
                               CholeskyOrdering::Nesdis}) {
      SparseCholesky chol({o, true});
      const double an = time_median(1, [&] { chol.analyse(*A); });
      double fa = NAN;
      try {
        fa = time_median(1, [&] { chol.factorize(*A); });
      } catch (const NumericalError&) {
      }
      fmt::print("| {} | {} | {} -> {} | {:.3g} | {:.3g} | {:.1f} | {:.1f} |\n", c.n, cand, to_string(o),
                 chol.stats().ordering, chol.stats().nnz_l, chol.stats().flops, an * 1e3, fa * 1e3);
    }
  }
}

// The numeric refill of the full Hessian on 1 and 2 OpenMP threads (gather per block row, no atomics), and
// its factorisation on 1 and 2 BLAS threads (OpenBLAS only; the reference BLAS has one).
void compare_threads(const SizeCase& c) {
  EnergyHessian H(c.energy, {HessianStencil::Full, true, true, CompactLumping::Polar}, c.red.slot());
  const int saved = omp_get_max_threads();
  std::vector<std::pair<int, double>> t;
  for (int th : {1, 2}) {
    omp_set_num_threads(th);
    t.emplace_back(th, time_median(c.args.repeats, [&] { H.assemble(c.X); }));
  }
  omp_set_num_threads(saved);
  fmt::print(
      "\nfull Hessian refill (PSD-projected): 1 thread {:.1f} ms, 2 threads {:.1f} ms (speed-up {:.2f})\n",
      t[0].second * 1e3, t[1].second * 1e3, t[0].second / t[1].second);
  const int blas_saved = blas_threads();
  SparseCholesky chol;
  chol.analyse(H.matrix());
  for (int th : {1, 2}) {
    if (!set_blas_threads(th) && th > 1) break;
    fmt::print("full Hessian factorize, {} BLAS thread(s): {:.1f} ms\n", th,
               1e3 * time_median(c.args.repeats, [&] { chol.factorize(H.matrix()); }));
  }
  set_blas_threads(blas_saved);
}

void run_size(const Args& args, double spacing, std::vector<Row>& rows) {
  const std::vector<std::string> overrides{fmt::format("geometry.node_spacing_m={}", spacing),
                                           "discretization.max_growths=10"};
  Scene scene = load_scene(args.scene, overrides);
  Simulation sim(scene);
  const Discretization& disc = sim.discretization();
  SizeCase c(args, spacing, sim);
  fmt::print("\n## spacing {:.3g} mm: {} nodes, {} free, mean K {:.1f}, {} tets, nodes with grown h: {}\n",
             spacing * 1e3, c.n, c.dim / 3, disc.mean_neighbours(), disc.tets().size(), disc.grown_nodes());
  set_mass_shift(c, disc);
  print_hessian_product_time(c);
  const double s1 = 1.0 / scene.settings<QuasiStaticSettings>("quasi_static").load_steps;
  const Vec3Array dp = set_rest_case(c, s1);
  set_drifted_case(c, scene, s1);
  set_predictor_case(c, dp, s1);

  const std::vector<Candidate> candidates{{"tet", HessianStencil::Full, CompactLumping::Polar},
                                          {"compact", HessianStencil::Compact, CompactLumping::Polar},
                                          {"c-rowsum", HessianStencil::Compact, CompactLumping::RowSum},
                                          {"c-drop", HessianStencil::Compact, CompactLumping::Drop},
                                          {"full", HessianStencil::Full, CompactLumping::Polar}};
  print_header();
  for (const Candidate& cd : candidates)
    for (bool shifted : {false, true}) {
      rows.push_back(measure_candidate(c, cd, shifted));
      print_row(rows.back());
    }
  if (args.orderings) compare_orderings(c);
  if (args.threads) compare_threads(c);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse(argc, argv);
    spdlog::set_level(spdlog::level::warn);
    fmt::print(
        "# bench_equilibrium_linear_algebra\nscene {}\nBLAS: {} (threads {}){}\nOpenMP max threads {}\n",
        args.scene, blas_library(), blas_threads(), blas_config().empty() ? "" : ", " + blas_config(),
        omp_get_max_threads());
    fmt::print(
        "PCG: relative residual {:.0e}, at most {} iterations; mass shift dt = {} s; medians of {} repeats\n",
        args.tol, args.max_iterations, args.dt, args.repeats);
    std::vector<Row> rows;
    for (double s : args.spacings) run_size(args, s, rows);
    fmt::print("\n# summary\n");
    print_header();
    for (const Row& r : rows) print_row(r);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
  return 0;
}
