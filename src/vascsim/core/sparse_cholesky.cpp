#include "vascsim/core/sparse_cholesky.hpp"

#include "vascsim/core/blas_control.hpp"

#include <cholmod.h>

#include <fmt/format.h>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string ordering_name(int cholmod_ordering) {
  switch (cholmod_ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "amd";
    case CHOLMOD_METIS:
      return "metis";
    case CHOLMOD_NESDIS:
      return "nesdis";
    case CHOLMOD_COLAMD:
      return "colamd";
    case CHOLMOD_POSTORDERED:
      return "natural (postordered)";
    default:
      return fmt::format("unknown ({})", cholmod_ordering);
  }
}

// A read-only CHOLMOD view of an Eigen matrix: lower triangle of a symmetric matrix (stype -1), no copy.
cholmod_sparse view_lower(const Eigen::SparseMatrix<double>& A) {
  if (!A.isCompressed()) throw std::invalid_argument("SparseCholesky: the matrix must be compressed");
  if (A.rows() != A.cols()) throw std::invalid_argument("SparseCholesky: the matrix must be square");
  cholmod_sparse s;
  std::memset(&s, 0, sizeof(s));
  s.nrow = static_cast<std::size_t>(A.rows());
  s.ncol = static_cast<std::size_t>(A.cols());
  s.nzmax = static_cast<std::size_t>(A.nonZeros());
  s.p = const_cast<int*>(A.outerIndexPtr());
  s.i = const_cast<int*>(A.innerIndexPtr());
  s.x = const_cast<double*>(A.valuePtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

}  // namespace

std::string to_string(CholeskyOrdering ordering) {
  switch (ordering) {
    case CholeskyOrdering::Default:
      return "default";
    case CholeskyOrdering::Amd:
      return "amd";
    case CholeskyOrdering::Metis:
      return "metis";
    case CholeskyOrdering::Nesdis:
      return "nesdis";
    case CholeskyOrdering::Natural:
      return "natural";
  }
  return "?";
}

struct SparseCholesky::Cholmod {
  cholmod_common c;
  cholmod_factor* L = nullptr;
  cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;  // solve output and workspace, reused
  Cholmod() { cholmod_start(&c); }
  ~Cholmod() {
    free_factor();
    cholmod_free_dense(&X, &c);
    cholmod_free_dense(&Y, &c);
    cholmod_free_dense(&E, &c);
    cholmod_finish(&c);
  }
  void free_factor() {
    if (L) cholmod_free_factor(&L, &c);
  }
};

SparseCholesky::SparseCholesky(const SparseCholeskyOptions& options)
    : options_(options), cm_(std::make_unique<Cholmod>()) {
  apply_default_blas_threads();
  cholmod_common& c = cm_->c;
  c.print = 0;  // failures are reported by exceptions, not on stderr
  c.error_handler = nullptr;
  c.supernodal = options.supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  c.final_ll = 1;  // simplicial: keep L L^T (as the supernodal factor), not L D L^T
  // A failed supernodal factorisation stops at the first non-positive pivot instead of finishing the work.
  c.quick_return_if_not_posdef = 1;
  if (options.ordering != CholeskyOrdering::Default) {
    c.nmethods = 1;
    c.method[0].ordering = options.ordering == CholeskyOrdering::Amd      ? CHOLMOD_AMD
                           : options.ordering == CholeskyOrdering::Metis  ? CHOLMOD_METIS
                           : options.ordering == CholeskyOrdering::Nesdis ? CHOLMOD_NESDIS
                                                                          : CHOLMOD_NATURAL;
    c.postorder = options.ordering != CholeskyOrdering::Natural;
  }
}

SparseCholesky::~SparseCholesky() = default;

bool SparseCholesky::analysed() const {
  return cm_->L != nullptr;
}

void SparseCholesky::analyse(const Eigen::SparseMatrix<double>& A) {
  const auto t0 = std::chrono::steady_clock::now();
  cholmod_sparse a = view_lower(A);
  cm_->free_factor();
  factorized_ = false;
  cm_->L = cholmod_analyze(&a, &cm_->c);
  if (!cm_->L || cm_->c.status < CHOLMOD_OK)
    throw NumericalError(
        fmt::format("sparse Cholesky: analysis of a {} x {} matrix failed (CHOLMOD status {}{})", A.rows(),
                    A.cols(), cm_->c.status,
                    cm_->c.status == CHOLMOD_NOT_INSTALLED   ? ": ordering not built into CHOLMOD"
                    : cm_->c.status == CHOLMOD_OUT_OF_MEMORY ? ": out of memory"
                                                             : ""));
  rows_ = A.rows();
  nnz_analysed_ = A.nonZeros();
  stats_ = SparseCholeskyStats{};
  stats_.ordering = ordering_name(cm_->L->ordering);
  stats_.nnz_l = cm_->c.lnz;
  stats_.flops = cm_->c.fl;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) stats_.nnz_a += it.row() >= j ? 1 : 0;
  stats_.analyse_s = seconds_since(t0);
}

void SparseCholesky::factorize(const Eigen::SparseMatrix<double>& A) {
  if (!analysed()) throw std::logic_error("SparseCholesky::factorize before analyse");
  if (A.rows() != rows_ || A.nonZeros() != nnz_analysed_)
    throw std::invalid_argument(
        "SparseCholesky::factorize: the matrix pattern differs from the analysed one");
  const auto t0 = std::chrono::steady_clock::now();
  cholmod_sparse a = view_lower(A);
  factorized_ = false;
  const int ok = cholmod_factorize(&a, cm_->L, &cm_->c);
  stats_.factorize_s = seconds_since(t0);
  if (!ok || cm_->c.status < CHOLMOD_OK)
    throw NumericalError(fmt::format("sparse Cholesky: factorisation failed (CHOLMOD status {}{})",
                                     cm_->c.status,
                                     cm_->c.status == CHOLMOD_OUT_OF_MEMORY ? ": out of memory" : ""));
  if (cm_->c.status == CHOLMOD_NOT_POSDEF || cm_->L->minor < cm_->L->n)
    throw NumericalError(
        fmt::format("sparse Cholesky: the matrix is not positive definite (the factorisation broke down at "
                    "column {} of {} "
                    "in the permuted order); a preconditioner matrix must be symmetric positive definite",
                    cm_->L->minor, cm_->L->n));
  factorized_ = true;
  stats_.supernodal = cm_->L->is_super != 0;
  stats_.stored_l = static_cast<double>(cm_->L->is_super ? cm_->L->xsize : cm_->L->nzmax);
  if (options_.single_precision_solves && stats_.supernodal) copy_to_single_precision();
}

void SparseCholesky::copy_to_single_precision() {
  const cholmod_factor& L = *cm_->L;
  SupernodalFactorView v;
  v.n = static_cast<int>(L.n);
  v.supernodes = static_cast<int>(L.nsuper);
  v.perm = static_cast<const int*>(L.Perm);
  v.super = static_cast<const int*>(L.super);
  v.row_start = static_cast<const int*>(L.pi);
  v.value_start = static_cast<const int*>(L.px);
  v.rows = static_cast<const int*>(L.s);
  v.values = static_cast<const double*>(L.x);
  single_.assign(v);
}

void SparseCholesky::compute(const Eigen::SparseMatrix<double>& A) {
  analyse(A);
  factorize(A);
}

void SparseCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!single_.empty() && factorized_) {
    const auto t0 = std::chrono::steady_clock::now();
    single_.solve(b, x);
    stats_.solve_s = seconds_since(t0);
    return;
  }
  solve_columns(b.data(), 1);
  x.resize(rows_);
  std::memcpy(x.data(), cm_->X->x, static_cast<std::size_t>(rows_) * sizeof(double));
}

void SparseCholesky::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) {
  if (B.rows() != rows_)
    throw std::invalid_argument("SparseCholesky::solve: right-hand sides of the wrong size");
  if (!single_.empty() && factorized_) {
    const auto t0 = std::chrono::steady_clock::now();
    single_.solve(B, X);
    stats_.solve_s = seconds_since(t0);
    return;
  }
  X.resize(rows_, B.cols());
  if (B.cols() == 0) return;
  solve_columns(B.data(), B.cols());
  std::memcpy(X.data(), cm_->X->x, static_cast<std::size_t>(rows_ * B.cols()) * sizeof(double));
}

void SparseCholesky::solve_columns(const double* b, Eigen::Index columns) {
  if (!factorized_) throw std::logic_error("SparseCholesky::solve without a factor");
  const auto t0 = std::chrono::steady_clock::now();
  cholmod_dense B;
  std::memset(&B, 0, sizeof(B));
  B.nrow = static_cast<std::size_t>(rows_);
  B.ncol = static_cast<std::size_t>(columns);
  B.nzmax = static_cast<std::size_t>(rows_ * columns);
  B.d = static_cast<std::size_t>(rows_);
  B.x = const_cast<double*>(b);
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, cm_->L, &B, nullptr, &cm_->X, nullptr, &cm_->Y, &cm_->E, &cm_->c))
    throw NumericalError(fmt::format("sparse Cholesky: solve failed (CHOLMOD status {})", cm_->c.status));
  stats_.solve_s = seconds_since(t0);
}

}  // namespace vascsim
