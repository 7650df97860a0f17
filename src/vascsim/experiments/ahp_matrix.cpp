#include "vascsim/experiments/ahp_matrix.hpp"

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <stdexcept>

#include "vascsim/core/error.hpp"

namespace vascsim::ahp {

namespace {

// Saaty (1980), Table of the random consistency index for n = 1..10.
constexpr std::array<double, kMaxMatrixSize> kRandomIndex = {0.0,  0.0,  0.58, 0.90, 1.12,
                                                             1.24, 1.32, 1.41, 1.45, 1.49};

// "3", "1/3", "0.333": the shortest readable form of a scale value.
std::string scale_value_text(double s) {
  if (s >= 1.0) return fmt::format("{}", static_cast<int>(std::lround(s)));
  return fmt::format("1/{}", static_cast<int>(std::lround(1.0 / s)));
}

// The Saaty scale value nearest to x (on a ratio scale), or 0 if x is outside [1/9, 9] by more than the
// tolerance.
double nearest_saaty(double x) {
  const long k = std::lround(x >= 1.0 ? x : 1.0 / x);
  if (k < 1 || k > 9) return 0.0;
  return x >= 1.0 ? static_cast<double>(k) : 1.0 / static_cast<double>(k);
}

// A decimal number with nothing else in the text (no "inf", "nan", hex, spaces inside).
bool parse_decimal(const std::string& text, double& out) {
  if (text.empty()) return false;
  for (char c : text)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E' || c == '+' ||
          c == '-'))
      return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(out);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

}  // namespace

JudgementScale parse_scale(const std::string& name) {
  if (name == "saaty") return JudgementScale::saaty;
  if (name == "aggregate") return JudgementScale::aggregate;
  if (name == "ratio") return JudgementScale::ratio;
  throw std::invalid_argument("unknown judgement scale '" + name + "'");
}

std::string to_string(JudgementScale scale) {
  switch (scale) {
    case JudgementScale::saaty:
      return "saaty";
    case JudgementScale::aggregate:
      return "aggregate";
    case JudgementScale::ratio:
      return "ratio";
  }
  return "?";
}

double random_index(int n) {
  if (n < 1 || n > kMaxMatrixSize)
    throw std::out_of_range(fmt::format("random index: n = {} outside 1..{}", n, kMaxMatrixSize));
  return kRandomIndex[static_cast<std::size_t>(n - 1)];
}

std::string MatrixSource::where() const {
  return name.empty() ? fmt::format("{}: key '{}'", file, key)
                      : fmt::format("{}: key '{}' ({})", file, key, name);
}

std::string MatrixSource::entry(int i, int j) const {
  const auto n = static_cast<int>(labels.size());
  if (i < n && j < n)
    return fmt::format("entry ({}, {})", labels[static_cast<std::size_t>(i)],
                       labels[static_cast<std::size_t>(j)]);
  return fmt::format("entry [{}][{}]", i + 1, j + 1);
}

Eigen::MatrixXd validate_pairwise(const Eigen::MatrixXd& a, JudgementScale scale,
                                  const MatrixSource& source) {
  const auto n = a.rows();
  if (a.rows() != a.cols())
    throw InputError(fmt::format("{}: the matrix is {}x{}; a pairwise comparison matrix is square",
                                 source.where(), a.rows(), a.cols()));
  if (n < 1 || n > kMaxMatrixSize)
    throw InputError(
        fmt::format("{}: {} rows; allowed 1..{} (Saaty's random index is tabulated up to n = {})",
                    source.where(), n, kMaxMatrixSize, kMaxMatrixSize));
  if (!source.labels.empty() && static_cast<std::size_t>(n) != source.labels.size())
    throw InputError(
        fmt::format("{}: the matrix has {} rows but {} elements are compared; one row per element, "
                    "in the order they are listed",
                    source.where(), n, source.labels.size()));
  const int m = static_cast<int>(n);
  // Entries: finite, positive, on the scale. Returns the value the computation uses.
  auto checked = [&](int i, int j) {
    const double x = a(i, j);
    if (!std::isfinite(x) || !(x > 0.0))
      throw InputError(fmt::format("{}: {} = {}; entries must be finite and positive", source.where(),
                                   source.entry(i, j), x));
    switch (scale) {
      case JudgementScale::saaty: {
        const double s = nearest_saaty(x);
        if (s == 0.0 || std::abs(x / s - 1.0) > kScaleTolerance)
          throw InputError(
              fmt::format("{}: {} = {} is not on Saaty's 1-9 scale (1..9 or 1/9..1/2{}); write reciprocals "
                          "as \"1/3\", or use "
                          "\"scale\": \"aggregate\" for averaged judgements",
                          source.where(), source.entry(i, j), x,
                          s == 0.0 ? ""
                                   : fmt::format("; nearest {} is more than {:g} % away", scale_value_text(s),
                                                 100 * kScaleTolerance)));
        return s;
      }
      case JudgementScale::aggregate:
        if (x < (1.0 - kScaleTolerance) / 9.0 || x > 9.0 * (1.0 + kScaleTolerance))
          throw InputError(
              fmt::format("{}: {} = {} is outside [1/9, 9], the range of averaged 1-9 judgements; use "
                          "\"scale\": \"ratio\" for ratios of known weights",
                          source.where(), source.entry(i, j), x));
        return x;
      case JudgementScale::ratio:
        return x;
    }
    return x;
  };
  Eigen::MatrixXd out = Eigen::MatrixXd::Ones(n, n);
  for (int i = 0; i < m; ++i) {
    if (!(std::abs(a(i, i) - 1.0) <= 1e-9))
      throw InputError(fmt::format("{}: {} = {}; the diagonal must be 1 (an element compared with itself)",
                                   source.where(), source.entry(i, i), a(i, i)));
    for (int j = i + 1; j < m; ++j) {
      const double upper = checked(i, j);
      checked(j, i);
      const double product = a(i, j) * a(j, i);
      if (std::abs(product - 1.0) > kReciprocalTolerance)
        throw InputError(
            fmt::format("{}: {} = {} and {} = {} are not reciprocal (product {:.4g}); a_ji must be "
                        "1/a_ij within {:g} %",
                        source.where(), source.entry(i, j), a(i, j), source.entry(j, i), a(j, i), product,
                        100 * kReciprocalTolerance));
      out(i, j) = upper;
      out(j, i) = 1.0 / upper;
    }
  }
  return out;
}

PairwiseAnalysis analyse_pairwise(const Eigen::MatrixXd& a) {
  const auto n = a.rows();
  PairwiseAnalysis r;
  if (n < 1 || a.cols() != n)
    throw NumericalError("analyse_pairwise: the matrix must be square and non-empty");
  if (n == 1) {
    r.weights = Eigen::VectorXd::Ones(1);
    r.lambda_max = 1.0;
    return r;
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> es(a, true);
  if (es.info() != Eigen::Success) throw NumericalError("analyse_pairwise: the eigen-decomposition failed");
  Eigen::Index k = 0;
  for (Eigen::Index i = 1; i < n; ++i)
    if (es.eigenvalues()[i].real() > es.eigenvalues()[k].real()) k = i;
  const std::complex<double> lambda = es.eigenvalues()[k];
  const Eigen::VectorXcd v = es.eigenvectors().col(k);
  // Perron-Frobenius: for a positive matrix the largest eigenvalue is real and simple, and its eigenvector
  // can be scaled to be positive.
  const double sum = v.real().sum();
  if (std::abs(lambda.imag()) > 1e-9 * std::abs(lambda) || v.imag().norm() > 1e-9 * v.norm() || sum == 0.0)
    throw NumericalError("analyse_pairwise: the principal eigenpair is not real (is the matrix positive?)");
  r.weights = v.real() / sum;
  if (!(r.weights.minCoeff() > 0.0))
    throw NumericalError(
        "analyse_pairwise: the principal eigenvector is not positive (is the matrix positive?)");
  r.lambda_max = lambda.real();
  if (n >= 3) {
    const double nn = static_cast<double>(n);
    // lambda_max >= n holds for every positive reciprocal matrix (Saaty 1980); the clamp only removes
    // round-off of a consistent matrix.
    r.ci = std::max(0.0, (r.lambda_max - nn) / (nn - 1.0));
    r.random_index = random_index(static_cast<int>(n));
    r.cr = r.ci / r.random_index;
  }
  return r;
}

PairwiseAnalysis check_pairwise(const Eigen::MatrixXd& a, JudgementScale scale, const MatrixSource& source,
                                double max_cr) {
  const PairwiseAnalysis r = analyse_pairwise(validate_pairwise(a, scale, source));
  if (r.cr > max_cr + 1e-12)
    throw InputError(
        fmt::format("{}: inconsistent judgements: consistency ratio CR = {:.4f} > {:g} (lambda_max = "
                    "{:.4f}, CI = {:.4f}, RI({}) = {:.2f}); revise the comparisons",
                    source.where(), r.cr, max_cr, r.lambda_max, r.ci, a.rows(), r.random_index));
  return r;
}

Eigen::MatrixXd parse_matrix(const nlohmann::json& value, const MatrixSource& source) {
  if (!value.is_array() || value.empty())
    throw InputError(fmt::format(
        "{}: expected a non-empty array of rows (arrays of numbers or \"p/q\" strings)", source.where()));
  const auto n = value.size();
  if (n > static_cast<std::size_t>(kMaxMatrixSize))
    throw InputError(
        fmt::format("{}: {} rows; allowed 1..{} (Saaty's random index is tabulated up to n = {})",
                    source.where(), n, kMaxMatrixSize, kMaxMatrixSize));
  Eigen::MatrixXd a(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto& row = value[i];
    if (!row.is_array() || row.size() != n)
      throw InputError(fmt::format("{}: row {} must be an array of {} entries (a square matrix of {} rows)",
                                   source.where(), i + 1, n, n));
    for (std::size_t j = 0; j < n; ++j) {
      const auto& e = row[j];
      const int ii = static_cast<int>(i), jj = static_cast<int>(j);
      double x = 0.0;
      if (e.is_number()) {
        x = e.get<double>();
      } else if (e.is_string()) {
        const std::string text = e.get<std::string>();
        const auto slash = text.find('/');
        double p = 0.0, q = 1.0;
        const bool ok = slash == std::string::npos ? parse_decimal(trim(text), p)
                                                   : parse_decimal(trim(text.substr(0, slash)), p) &&
                                                         parse_decimal(trim(text.substr(slash + 1)), q);
        if (!ok || !(p > 0.0) || !(q > 0.0))
          throw InputError(fmt::format("{}: {} = \"{}\" is not a positive number or fraction \"p/q\"",
                                       source.where(), source.entry(ii, jj), text));
        x = p / q;
      } else {
        throw InputError(fmt::format("{}: {} must be a number or a fraction string \"p/q\"", source.where(),
                                     source.entry(ii, jj)));
      }
      a(ii, jj) = x;
    }
  }
  return a;
}

}  // namespace vascsim::ahp
