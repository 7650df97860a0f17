#include "vascsim/model/discretization.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "vascsim/core/error.hpp"
#include "vascsim/core/kernels.hpp"
#include "vascsim/core/spatial_grid.hpp"

namespace vascsim {

// Neighbourhood of one node at a trial radius: weights, A_i and the conditioning verdict.
struct NeighbourhoodTrial {
  std::vector<Index> nbr;
  std::vector<double> w;
  Mat3 A = Mat3::Zero();
  double eigen_ratio = 0.0;
  double fit_ratio = 1.0;  // quadratic basis: lambda_min / lambda_max of B_i / tr(B_i)
};

namespace {

// The fitted monomials of X_ij for node i: the quadratic basis's (global frame), or the wall-quadratic
// basis's in the frame of the node's wall normal (local_fit.hpp).
Vec9 fit_monomials(GradientBasis basis, const Vec3& X, double h, const Vec3* normal) {
  return basis == GradientBasis::WallQuadratic ? wall_quadratic_monomials(X, h, *normal)
                                               : quadratic_monomials(X, h);
}

// B_i = sum_j w_ij p_ij p_ij^T of a curvature-fitting basis (local_fit.hpp), monomials scaled by h. The
// wall-quadratic basis has 8 monomials: its unused ninth row and column get the mean eigenvalue, so that B_i
// stays invertible (its inverse leaves the ninth coefficient zero) and its eigenvalue ratio is the 8 x 8
// block's.
Mat9 quadratic_moment(const Vec3Array& X, Index i, const NeighbourhoodTrial& t, double h, GradientBasis basis,
                      const Vec3* normal) {
  Mat9 B = Mat9::Zero();
  for (std::size_t a = 0; a < t.nbr.size(); ++a) {
    const Vec9 p = fit_monomials(basis, X[t.nbr[a]] - X[i], h, normal);
    B.noalias() += t.w[a] * p * p.transpose();
  }
  if (basis == GradientBasis::WallQuadratic) B(8, 8) = B.trace() / 8.0;
  return B;
}

double eigen_ratio_of(const Mat9& B) {
  const double tr = B.trace();
  if (!(tr > 0.0)) return 0.0;
  Eigen::SelfAdjointEigenSolver<Mat9> es(B / tr, Eigen::EigenvaluesOnly);
  return es.eigenvalues().maxCoeff() > 0.0 ? es.eigenvalues().minCoeff() / es.eigenvalues().maxCoeff() : 0.0;
}

// The distance that measures a node's support: |X| (isotropic), or, for a support that follows the wall,
// radius h through the wall and stretch h along it: with the nodes' wall depths d, the through-wall part of
// X_ij is d_j - d_i and the rest lies along the wall (so a layer of a curved wall stays one layer at any
// distance); without depths, the part along the node's normal n (the tangent plane of a flat wall). The
// through-wall distance may be scaled by across_scale <= 1 (WallReach::Thickness), so that the support holds
// the whole wall while its reach along the wall stays.
struct SupportMetric {
  const Vec3* normal = nullptr;
  double stretch = 1.0;
  const std::vector<double>* depth = nullptr;  ///< per node, m (empty: use the normal)
  Index i = 0;
  double across_scale = 1.0;
  const Vec3* axis =
      nullptr;  ///< a direction in the wall with its own stretch (null: one stretch in the wall)
  double axial_stretch = 1.0;
  double operator()(const Vec3& X, Index j) const {
    if (!normal) return X.norm();
    const double across = depth
                              ? (*depth)[static_cast<std::size_t>(j)] - (*depth)[static_cast<std::size_t>(i)]
                              : X.dot(*normal);
    const double along2 = std::max(0.0, X.squaredNorm() - across * across);
    const double c = across_scale * across;
    if (!axis) return std::sqrt(c * c + along2 / (stretch * stretch));
    const double axial = X.dot(*axis), around2 = std::max(0.0, along2 - axial * axial);
    return std::sqrt(c * c + around2 / (stretch * stretch) + axial * axial / (axial_stretch * axial_stretch));
  }
  // The largest distance inside the support.
  double reach(double h) const {
    return normal ? std::max({stretch, axis ? axial_stretch : 1.0, 1.0 / across_scale}) * h : h;
  }
};

SupportMetric support_metric(const DiscretizationOptions& opt, Index i, double across_scale) {
  if (opt.support != DiscretizationOptions::Support::Wall) return {};
  const auto k = static_cast<std::size_t>(i);
  const double stretch = opt.wall_stretches.empty() ? opt.wall_stretch : opt.wall_stretches[k];
  SupportMetric m{&opt.wall_normals[k], stretch, opt.wall_depths.empty() ? nullptr : &opt.wall_depths, i,
                  across_scale};
  if (!opt.wall_axes.empty()) {
    m.axis = &opt.wall_axes[k];
    m.axial_stretch = opt.wall_axial_stretches[k];
  }
  return m;
}

// The largest stretch of any node's support (the spatial grid's reach).
double largest_stretch(const DiscretizationOptions& opt) {
  double s = opt.wall_stretch;
  for (double v : opt.wall_stretches) s = std::max(s, v);
  for (double v : opt.wall_axial_stretches) s = std::max(s, v);
  return s;
}

// WallReach::Thickness: the wall's far surface at this fraction of h_0 (poly6 weight 8 % of the centre's),
// inside the support so that a fit across the wall is conditioned, the nearer layers still weighing most.
constexpr double kThicknessReach = 0.75;

// DiscretizationOptions::wall_cube: the through-wall cube counts as resolved when the support holds at least
// four of the wall's depths (a cube through three is a quadratic through them) and its residual after the
// quadratic fit keeps at least this fraction of its weighted square (on a flat wall of three layers it is
// zero to rounding, on four about 0.1-0.5). The count matters on a curved wall: there a neighbour on the
// node's own layer lies off its tangent plane, so z^3 keeps a small residual on three layers, and fitting it
// amplifies the curvature's trace into the gradients (the catheter on the vein with three layers was 11-18 %
// stiff).
constexpr double kCubeResolvable = 1e-8;
constexpr int kCubeDepths = 4;
// Two depths count as one layer when they differ by less than this fraction of the layer spacing.
constexpr double kSameLayer = 0.25;

// The number of distinct wall depths among node i and its neighbours (kSameLayer of the layer spacing apart).
int support_depths(Index i, const std::vector<Index>& nbr, const DiscretizationOptions& opt) {
  std::vector<double> d{opt.wall_depths[static_cast<std::size_t>(i)]};
  for (Index j : nbr) d.push_back(opt.wall_depths[static_cast<std::size_t>(j)]);
  std::sort(d.begin(), d.end());
  const double tol = kSameLayer * opt.wall_layer_spacing_m;
  int layers = 1;
  for (std::size_t a = 1; a < d.size(); ++a)
    if (d[a] - d[a - 1] > tol) ++layers;
  return layers;
}

NeighbourhoodTrial evaluate(const Vec3Array& X, Index i, double h, const SpatialGrid& grid,
                            GradientBasis basis, const SupportMetric& metric, const Vec3* fit_normal) {
  NeighbourhoodTrial t;
  grid.for_each_within(X[i], metric.reach(h), [&](Index j, double) {
    // A wall lattice puts whole layers and rows exactly on the ellipsoid's edge, where the weight is zero:
    // they are left out (within rounding), not kept as neighbours of weight ~1e-30 that would only widen the
    // stencils.
    if (j != i && (!metric.normal || metric(X[j] - X[i], j) < h * (1.0 - 1e-9))) t.nbr.push_back(j);
  });
  std::sort(t.nbr.begin(), t.nbr.end());
  for (Index j : t.nbr) {
    const Vec3 Xij = X[j] - X[i];
    const double w = kernels::poly6(metric(Xij, j), h);
    t.w.push_back(w);
    t.A += w * Xij * Xij.transpose();
  }
  const double tr = t.A.trace();
  if (tr > 0.0) {
    // Dimensionless A / tr(A): eigenvalues in (0, 1]; never test det(A) != 0 (docs/model/05-local-fit.md).
    Eigen::SelfAdjointEigenSolver<Mat3> es(t.A / tr, Eigen::EigenvaluesOnly);
    const Vec3 ev = es.eigenvalues();
    t.eigen_ratio = ev.maxCoeff() > 0.0 ? ev.minCoeff() / ev.maxCoeff() : 0.0;
  }
  if (fits_curvature(basis)) t.fit_ratio = eigen_ratio_of(quadratic_moment(X, i, t, h, basis, fit_normal));
  return t;
}

PairTable transpose(const PairTable& p, Index n) {
  PairTable t;
  t.row_start.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Index j : p.col) ++t.row_start[j + 1];
  std::partial_sum(t.row_start.begin(), t.row_start.end(), t.row_start.begin());
  t.col.resize(p.col.size());
  t.d.resize(p.col.size());
  t.w.resize(p.col.size());
  const std::size_t G = p.col.empty() ? 0 : p.e.size() / p.col.size();
  t.e.resize(p.e.size());
  std::vector<Index> fill(t.row_start.begin(), t.row_start.end() - 1);
  for (Index i = 0; i < n; ++i)
    for (Index e = p.row_start[i]; e < p.row_start[i + 1]; ++e) {
      const Index k = p.col[e];
      const Index slot = fill[k]++;
      t.col[slot] = i;  // rows i are visited in order, so every transposed row is sorted
      t.d[slot] = p.d[e];
      t.w[slot] = p.w[e];
      for (std::size_t k = 0; k < G; ++k)
        t.e[static_cast<std::size_t>(slot) * G + k] = p.e[static_cast<std::size_t>(e) * G + k];
    }
  return t;
}

// The neighbours a support needs: the linear basis's minimum, or the quadratic fit's when that is larger. The
// wall-quadratic fit keeps the linear minimum (docs/model/05-local-fit.md section 5.2: asking it 18 grew a
// third of the vein's supports and changed its force by 0.3 %); its conditioning test alone guards its 8
// unknowns.
int needed_neighbours(const DiscretizationOptions& opt) {
  return opt.basis == GradientBasis::Quadratic ? std::max(opt.min_neighbours, opt.quadratic_min_neighbours)
                                               : opt.min_neighbours;
}

// The support guard: enough neighbours, not coplanar, and (quadratic basis) a well-posed quadratic fit.
bool accepted(const NeighbourhoodTrial& t, const DiscretizationOptions& opt) {
  return static_cast<int>(t.nbr.size()) >= needed_neighbours(opt) && t.eigen_ratio >= opt.min_eigen_ratio &&
         (!fits_curvature(opt.basis) || t.fit_ratio >= opt.quadratic_min_eigen_ratio);
}

}  // namespace

Discretization::Discretization(const NodeCloud& cloud, const Material& material,
                               const DiscretizationOptions& options)
    : cloud_(cloud),
      material_(material),
      X_(cloud.positions),
      tets_(cloud.tets),
      wall_stretch_(options.wall_normals.empty() ? 0.0 : options.wall_stretch) {
  if (X_.size() < 5)
    throw InputError(fmt::format("discretization: {} nodes; at least 5 are needed", X_.size()));
  if (!(options.support_radius_factor > 0.0))
    throw InputError("discretization: support radius factor must be > 0");
  for (std::size_t i = 0; i < X_.size(); ++i)
    if (!X_[i].allFinite())
      throw InputError(fmt::format("discretization: node {} has a non-finite position", i));
  for (const Tet& t : tets_)
    for (Index v : t)
      if (v < 0 || v >= num_nodes())
        throw InputError("discretization: a tetrahedron references a missing node");
  mean_spacing_ = mean_nearest_spacing(X_);
  min_spacing_ = min_nearest_spacing(X_);
  if (!(min_spacing_ > 1e-9 * mean_spacing_))
    throw InputError("discretization: two nodes coincide (nearest-neighbour distance is zero)");
  build_neighbourhoods(options);
  compute_volumes(options);
}

void Discretization::build_neighbourhoods(const DiscretizationOptions& opt) {
  const Index n = num_nodes();
  const double h0 = opt.support_radius_factor * mean_spacing_;
  const bool wall = opt.support == DiscretizationOptions::Support::Wall;
  if (wall && (opt.wall_normals.size() != static_cast<std::size_t>(n) || !(opt.wall_stretch >= 1.0)))
    throw InputError(
        fmt::format("discretization: wall-aligned supports need one wall normal per node ({} for {} nodes) "
                    "and a stretch >= 1 ({})",
                    opt.wall_normals.size(), n, opt.wall_stretch));
  if (wall && (opt.wall_axes.size() != opt.wall_axial_stretches.size() ||
               (!opt.wall_axes.empty() && opt.wall_axes.size() != opt.wall_stretches.size()) ||
               !std::all_of(opt.wall_axial_stretches.begin(), opt.wall_axial_stretches.end(),
                            [](double v) { return v >= 1.0; })))
    throw InputError(
        fmt::format("discretization: {} wall axes and {} axial stretches (each >= 1) for {} per-node "
                    "stretches",
                    opt.wall_axes.size(), opt.wall_axial_stretches.size(), opt.wall_stretches.size()));
  if (wall && !opt.wall_stretches.empty() &&
      (opt.wall_stretches.size() != static_cast<std::size_t>(n) ||
       !std::all_of(opt.wall_stretches.begin(), opt.wall_stretches.end(), [](double v) { return v >= 1.0; })))
    throw InputError(fmt::format("discretization: {} per-node wall stretches for {} nodes; each must be >= 1",
                                 opt.wall_stretches.size(), n));
  if (wall && !opt.wall_depths.empty() && opt.wall_depths.size() != static_cast<std::size_t>(n))
    throw InputError(fmt::format("discretization: {} wall depths for {} nodes", opt.wall_depths.size(), n));
  if (wall && opt.wall_reach == DiscretizationOptions::WallReach::Thickness) {
    if (!(opt.wall_thickness_m > 0.0))
      throw InputError(
          "discretization: a support that reaches through the wall's thickness needs the wall's thickness");
    wall_across_scale_ = std::min(1.0, kThicknessReach * h0 / opt.wall_thickness_m);
  }
  const double hmax = h0 * std::pow(opt.growth_factor, opt.max_growths) *
                      (wall ? std::max(largest_stretch(opt), 1.0 / wall_across_scale_) : 1.0);
  SpatialGrid grid(X_, hmax);
  h_.assign(n, h0);
  std::vector<NeighbourhoodTrial> trials(n);
  std::vector<int> failed(n, 0);
  const bool quadratic = fits_curvature(opt.basis);
  const int min_neighbours = needed_neighbours(opt);
  if (opt.basis == GradientBasis::WallQuadratic) {
    if (opt.wall_normals.size() != static_cast<std::size_t>(n))
      throw InputError(
          fmt::format("discretization: the wall-quadratic basis needs one wall normal per node ({} for {} "
                      "nodes)",
                      opt.wall_normals.size(), n));
    fit_normals_ = opt.wall_normals;
  }
  place_wall_points(opt);
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    double h = h0;
    for (int g = 0;; ++g) {
      const SupportMetric metric = support_metric(opt, i, wall_across_scale_);
      trials[i] = evaluate(X_, i, h, grid, opt.basis, metric, fit_normal(i));
      if (accepted(trials[i], opt)) break;
      if (g == opt.max_growths) {
        failed[i] = 1;
        break;
      }
      h *= opt.growth_factor;
    }
    h_[i] = h;
  }
  const auto first_failed = std::find(failed.begin(), failed.end(), 1);
  if (first_failed != failed.end()) {
    const Index i = static_cast<Index>(first_failed - failed.begin());
    const Vec3& p = X_[i];
    const std::string fit =
        quadratic ? fmt::format(", ratio {:.3g} of the quadratic fit's B_i/tr(B_i) (need >= {:.1g})",
                                trials[i].fit_ratio, opt.quadratic_min_eigen_ratio)
                  : std::string();
    throw NumericalError(fmt::format(
        "discretization: node {} at ({:.6g}, {:.6g}, {:.6g}) m has {} neighbours and eigenvalue ratio {:.3g} "
        "of A_i/tr(A_i){} even at support radius {:.4g} m (need >= {} neighbours and ratio >= {:.1g}): its "
        "neighbourhood is too sparse or coplanar ({} of {} nodes fail): {}",
        i, p.x(), p.y(), p.z(), trials[i].nbr.size(), trials[i].eigen_ratio, fit, h_[i], min_neighbours,
        opt.min_eigen_ratio, std::count(failed.begin(), failed.end(), 1), n, growth_advice(failed, h0, opt)));
  }
  grown_nodes_ = static_cast<int>(std::count_if(h_.begin(), h_.end(), [h0](double h) { return h > h0; }));
  if (grown_nodes_ > 0)
    spdlog::info("discretization: support radius grown for {} of {} nodes (K_min / conditioning guard)",
                 grown_nodes_, n);

  store_gradient_vectors(trials, opt);
  transposed_ = transpose(pairs_, n);
}

// What fixes a failed support guard, for its message: the smallest discretization.max_growths (the key is
// read in [0, kMaxGrowthsAllowed]) with which every failed node passes, or, when none does, a finer spacing.
std::string Discretization::growth_advice(const std::vector<int>& failed, double h0,
                                          const DiscretizationOptions& opt) const {
  constexpr int kMaxGrowthsAllowed = 10;
  const bool wall = opt.support == DiscretizationOptions::Support::Wall;
  const double hmax = h0 * std::pow(opt.growth_factor, kMaxGrowthsAllowed) *
                      (wall ? std::max(largest_stretch(opt), 1.0 / wall_across_scale_) : 1.0);
  const SpatialGrid grid(X_, hmax);
  int needed = opt.max_growths;
  for (std::size_t i = 0; i < failed.size() && needed <= kMaxGrowthsAllowed; ++i) {
    if (!failed[i]) continue;
    const SupportMetric metric = support_metric(opt, static_cast<Index>(i), wall_across_scale_);
    for (int g = opt.max_growths + 1;; ++g) {
      if (g > kMaxGrowthsAllowed) {
        needed = g;
        break;
      }
      const NeighbourhoodTrial t = evaluate(X_, static_cast<Index>(i), h0 * std::pow(opt.growth_factor, g),
                                            grid, opt.basis, metric, fit_normal(static_cast<Index>(i)));
      if (accepted(t, opt)) {
        needed = std::max(needed, g);
        break;
      }
    }
  }
  // A lattice too coarse for its wall is fixed by a finer one: growths would make it run, inaccurately.
  const std::string first = opt.coarse_spacing_advice.empty() ? "" : opt.coarse_spacing_advice + "; ";
  if (needed <= kMaxGrowthsAllowed)
    return fmt::format(
        "{}{}let the support grow further: discretization.max_growths = {} makes every node pass (now "
        "{})",
        first, first.empty() ? "" : "or ", needed, opt.max_growths);
  return fmt::format(
      "{}even discretization.max_growths = {} does not help (now {}): use a finer geometry.node_spacing_m",
      first, kMaxGrowthsAllowed, opt.max_growths);
}

// The accepted neighbourhoods as the pair tables: d_ij (linear or quadratic fit), w_ij, d_ii and the moments.
void Discretization::store_gradient_vectors(const std::vector<NeighbourhoodTrial>& trials,
                                            const DiscretizationOptions& opt) {
  const GradientBasis basis = opt.basis;
  const Index n = num_nodes();
  const bool quadratic = fits_curvature(basis);
  pairs_.row_start.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Index i = 0; i < n; ++i)
    pairs_.row_start[i + 1] = pairs_.row_start[i] + static_cast<Index>(trials[i].nbr.size());
  const std::size_t npairs = static_cast<std::size_t>(pairs_.row_start[n]);
  pairs_.col.resize(npairs);
  pairs_.d.resize(npairs);
  pairs_.w.resize(npairs);
  self_d_.assign(n, Vec3::Zero());
  moment_trace_.assign(n, 0.0);
  moment_.assign(n, Mat3::Zero());
  basis_ = basis;
  if (quadratic) fit_.resize(npairs);
  const bool points = energy_points_ > 1;
  const std::size_t G = static_cast<std::size_t>(point_directions_);
  if (points) {
    pairs_.e.resize(npairs * G);
    self_e_.assign(static_cast<std::size_t>(n) * G, Vec3::Zero());
  }
  if (opt.wall_cube) {
    if (basis != GradientBasis::Quadratic || opt.wall_normals.size() != static_cast<std::size_t>(n))
      throw InputError(
          "discretization: the through-wall cube (wall_cube) extends the quadratic basis on a wall and "
          "needs basis 'quadratic' and one wall normal per node (discretization.support 'wall')");
  }
  int cubes = 0;
#pragma omp parallel for schedule(static) reduction(+ : cubes)
  for (Index i = 0; i < n; ++i) {
    const NeighbourhoodTrial& t = trials[i];
    const Mat3 Ainv = t.A.inverse();  // well conditioned by the guard above (double precision)
    moment_trace_[i] = t.A.trace();
    moment_[i] = t.A;
    Mat9 Binv;
    if (quadratic)
      Binv = quadratic_moment(X_, i, t, h_[i], basis, fit_normal(i))
                 .inverse();  // conditioned by the guard (double)
    Vec3 dsum = Vec3::Zero();
    std::array<Vec3, kMaxPointDirections> esum;
    esum.fill(Vec3::Zero());
    // Gauss points: the fit's gradient along the point direction u_k changes by c_ij^T M_k / h^2 per metre.
    std::array<Eigen::Matrix<double, 9, 3>, kMaxPointDirections> M;
    // The directions of the offsets' products (the cubics', after the linear ones) get their vectors from
    // add_wall_cube / add_wall_cubics: the quadratic part of the gradient does not change with them.
    const std::size_t fitted = static_cast<std::size_t>(linear_directions_);
    for (std::size_t k = 0; k < G; ++k)
      M[k] = k < fitted ? monomial_hessians_along(basis, point_axes_[static_cast<std::size_t>(i) * G + k],
                                                  *fit_normal_or(i, opt))
                        : Eigen::Matrix<double, 9, 3>::Zero();
    for (std::size_t a = 0; a < t.nbr.size(); ++a) {
      const Index e = pairs_.row_start[i] + static_cast<Index>(a);
      const Vec3 Xij = X_[t.nbr[a]] - X_[i];
      pairs_.col[e] = t.nbr[a];
      pairs_.w[e] = t.w[a];
      if (quadratic) {
        fit_[e] = t.w[a] * (Binv * fit_monomials(basis, Xij, h_[i], fit_normal(i)));
        pairs_.d[e] = fit_[e].head<3>() / h_[i];  // the gradient rows of the fit, per metre
        for (std::size_t k = 0; k < G; ++k) {
          Vec3& ek = pairs_.e[static_cast<std::size_t>(e) * G + k];
          ek = (fit_[e].transpose() * M[k]).transpose() / (h_[i] * h_[i]);
        }
      } else {
        pairs_.d[e] = t.w[a] * (Ainv * Xij);
      }
    }
    if (opt.wall_cube) {
      const bool mixed = opt.wall_cubics != DiscretizationOptions::WallCubics::Cube;
      if ((mixed && add_wall_cubics(i, t.nbr, opt)) ||
          add_wall_cube(i, opt.wall_normals[static_cast<std::size_t>(i)], t.nbr, opt))
        ++cubes;
    }
    for (Index e = pairs_.row_start[i]; e < pairs_.row_start[i + 1]; ++e) {
      dsum += pairs_.d[e];
      for (std::size_t k = 0; k < G; ++k) esum[k] += pairs_.e[static_cast<std::size_t>(e) * G + k];
    }
    self_d_[i] = -dsum;
    for (std::size_t k = 0; k < G; ++k) self_e_[static_cast<std::size_t>(i) * G + k] = -esum[k];
  }
  cube_nodes_ = cubes;
}

// DiscretizationOptions::wall_cube for node i (docs/model/05-local-fit.md section 5.3): the least-squares fit
// over the quadratic monomials p and the cube m = (z / h)^3 of the through-wall coordinate z = X_ij . n, by
// eliminating m's coefficient. With m~ the residual of m after the quadratic fit (orthogonal to p in the
// weights w), the cube's coefficient is c(y) = sum_j beta_j (y_j - y_i) with
// beta_j = w_j m~_j / sum_l w_l m~_l^2, and every quadratic coefficient loses c(y) times the quadratic fit's
// coefficient of m: the node's gradient vectors d_ij and their derivatives e_ij,k lose beta_j times the
// quadratic fit's gradient (and derivatives) of m. The cube's own gradient is zero at the node and
// 3 o^2 / h^3 n at a point offset o along n: the first point direction after the linear ones, whose offset is
// o^2.
bool Discretization::add_wall_cube(Index i, const Vec3& normal, const std::vector<Index>& nbr,
                                   const DiscretizationOptions& opt) {
  if (opt.wall_depths.size() == static_cast<std::size_t>(num_nodes()) &&
      support_depths(i, nbr, opt) < kCubeDepths)
    return false;
  const Index e0 = pairs_.row_start[i];
  const std::size_t K = nbr.size(), G = static_cast<std::size_t>(point_directions_);
  const double h = h_[i];
  std::vector<double> m(K), residual(K);
  Vec9 coeff = Vec9::Zero();  // the quadratic fit of m: sum_j fit_ij m_j
  double plain = 0.0;
  for (std::size_t a = 0; a < K; ++a) {
    const double z = (X_[nbr[a]] - X_[i]).dot(normal) / h;
    m[a] = z * z * z;
    coeff += fit_[static_cast<std::size_t>(e0) + a] * m[a];
    plain += pairs_.w[static_cast<std::size_t>(e0) + a] * m[a] * m[a];
  }
  double S = 0.0;
  for (std::size_t a = 0; a < K; ++a) {
    residual[a] = m[a] - coeff.dot(quadratic_monomials(X_[nbr[a]] - X_[i], h));
    S += pairs_.w[static_cast<std::size_t>(e0) + a] * residual[a] * residual[a];
  }
  // A neighbourhood of three depths on a flat wall fits z^3 with z exactly: no cube to add.
  if (!(S > kCubeResolvable * plain)) return false;
  // The quadratic fit's gradient of m and its derivatives along the point directions.
  Vec3 gm = Vec3::Zero();
  std::array<Vec3, kMaxPointDirections> em;
  em.fill(Vec3::Zero());
  for (std::size_t a = 0; a < K; ++a) {
    const std::size_t e = static_cast<std::size_t>(e0) + a;
    gm += pairs_.d[e] * m[a];
    for (std::size_t k = 0; k < G; ++k) em[k] += pairs_.e[e * G + k] * m[a];
  }
  const double h3 = h * h * h;
  for (std::size_t a = 0; a < K; ++a) {
    const std::size_t e = static_cast<std::size_t>(e0) + a;
    const double beta = pairs_.w[e] * residual[a] / S;
    pairs_.d[e] -= beta * gm;
    for (std::size_t k = 0; k < G; ++k) pairs_.e[e * G + k] -= beta * em[k];
    // The cube's gradient 3 o^2 / h^3 n at the offset o along n: its own direction, the first after the
    // linear ones.
    if (G > 0) pairs_.e[e * G + static_cast<std::size_t>(linear_directions_)] += beta * 3.0 / h3 * normal;
  }
  return true;
}

namespace {
// The wall frame's coordinates (z through the wall, s1 and s2 along the cell's edges) as exponents: the six
// cubics with a through-wall factor, z^3 (add_wall_cube's) first, and the six products of two coordinates, in
// the order of the point directions after the linear ones. (The cubics along the wall alone, s1^3 ..., are
// left out: a support that spans three columns along the wall cannot tell s^3 from s.)
using Exponents = std::array<int, 3>;
constexpr std::array<Exponents, 6> kCubics{
    {{3, 0, 0}, {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {1, 1, 1}, {1, 0, 2}}};
constexpr std::array<Exponents, 6> kSquares{
    {{2, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0, 2, 0}, {0, 1, 1}, {0, 0, 2}}};

double monomial(const Exponents& e, const Vec3& c) {
  double v = 1.0;
  for (int k = 0; k < 3; ++k)
    for (int p = 0; p < e[static_cast<std::size_t>(k)]; ++p) v *= c[k];
  return v;
}

int square_index(const Exponents& e) {
  for (std::size_t a = 0; a < kSquares.size(); ++a)
    if (kSquares[a] == e) return static_cast<int>(a);
  return -1;
}
}  // namespace

// DiscretizationOptions::WallCubics::ThroughWall for node i (docs/model/05-local-fit.md section 5.4):
// add_wall_cube's elimination with R monomials m_r at once. With M~ the residuals of the m_r after the
// quadratic fit, the cubics' coefficients are c_r(y) = sum_j beta_rj (y_j - y_i) with beta = S^-1 (w M~)^T, S
// = M~^T W M~ (R x R); every quadratic coefficient loses sum_r c_r(y) times the quadratic fit's of m_r. A
// cubic's gradient is zero at the node and quadratic in a point's offset: its derivatives go to the
// directions of the offsets' products. z^3 joins only where the support holds four depths (add_wall_cube).
bool Discretization::add_wall_cubics(Index i, const std::vector<Index>& nbr,
                                     const DiscretizationOptions& opt) {
  const std::size_t ii = static_cast<std::size_t>(i), G = static_cast<std::size_t>(point_directions_);
  const std::size_t L = static_cast<std::size_t>(linear_directions_);
  if (L != 3 || G != L + kSquares.size()) return false;  // the cell's points (checked by place_wall_points)
  const std::array<Vec3, 3> axes{opt.wall_normals[ii], point_axes_[ii * G + 1], point_axes_[ii * G + 2]};
  const bool cube = opt.wall_depths.size() != static_cast<std::size_t>(num_nodes()) ||
                    support_depths(i, nbr, opt) >= kCubeDepths;
  const std::vector<Exponents> terms(kCubics.begin() + (cube ? 0 : 1), kCubics.end());
  const Eigen::Index R = static_cast<Eigen::Index>(terms.size()), K = static_cast<Eigen::Index>(nbr.size());
  const Index e0 = pairs_.row_start[i];
  const double h = h_[i];
  Eigen::MatrixXd m(K, R), residual(K, R), Pq(K, 9);  // Pq: the quadratic monomials over the stencil
  Eigen::VectorXd w(K);
  for (Eigen::Index a = 0; a < K; ++a) {
    const Vec3 X = X_[nbr[static_cast<std::size_t>(a)]] - X_[i];
    const Vec3 c(X.dot(axes[0]) / h, X.dot(axes[1]) / h, X.dot(axes[2]) / h);
    for (Eigen::Index r = 0; r < R; ++r) m(a, r) = monomial(terms[static_cast<std::size_t>(r)], c);
    w(a) = pairs_.w[static_cast<std::size_t>(e0 + a)];
    Pq.row(a) = quadratic_monomials(X, h).transpose();
  }
  for (Eigen::Index r = 0; r < R; ++r) {
    Vec9 coeff = Vec9::Zero();  // the quadratic fit of m_r
    for (Eigen::Index a = 0; a < K; ++a) coeff += fit_[static_cast<std::size_t>(e0 + a)] * m(a, r);
    for (Eigen::Index a = 0; a < K; ++a) residual(a, r) = m(a, r) - Pq.row(a).dot(coeff);
  }
  // Resolvable: the residuals' Gram matrix, scaled by each monomial's own weighted square, keeps its smallest
  // eigenvalue above add_wall_cube's fraction.
  const Eigen::MatrixXd S = residual.transpose() * w.asDiagonal() * residual;
  const Eigen::VectorXd plain = (m.array().square().colwise() * w.array()).colwise().sum().transpose();
  if (!(plain.minCoeff() > 0.0)) return false;
  const Eigen::VectorXd scale = plain.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = scale.asDiagonal() * S * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled, Eigen::EigenvaluesOnly);
  if (!(eig.eigenvalues()(0) > kCubeResolvable)) return false;
  Eigen::MatrixXd beta = S.ldlt().solve(residual.transpose() * w.asDiagonal());  // R x K
  // The cubics' coefficients vanish on every quadratic field in exact arithmetic; the quadratic fit's B_i^-1
  // (conditioned to 1e6) leaves a rounding of it that the elimination amplifies (a rigid motion's forces 200
  // times the cube's). Projecting each row of beta out of the span of the quadratic monomials over the
  // stencil, with Householder's orthogonal basis of it, restores it to rounding.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(Pq);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(K, 9);
  beta -= (beta * Q) * Q.transpose();
  // The quadratic fit's gradient of each m_r and its derivatives along the linear point directions.
  std::vector<Vec3> gm(static_cast<std::size_t>(R), Vec3::Zero());
  std::vector<std::array<Vec3, 3>> em(static_cast<std::size_t>(R));
  for (Eigen::Index r = 0; r < R; ++r) {
    em[static_cast<std::size_t>(r)].fill(Vec3::Zero());
    for (Eigen::Index a = 0; a < K; ++a) {
      const std::size_t e = static_cast<std::size_t>(e0 + a);
      gm[static_cast<std::size_t>(r)] += pairs_.d[e] * m(a, r);
      for (std::size_t k = 0; k < L; ++k) em[static_cast<std::size_t>(r)][k] += pairs_.e[e * G + k] * m(a, r);
    }
  }
  const double h3 = h * h * h;
  for (Eigen::Index a = 0; a < K; ++a) {
    const std::size_t e = static_cast<std::size_t>(e0 + a);
    for (Eigen::Index r = 0; r < R; ++r) {
      const double b = beta(r, a);
      const Exponents& ex = terms[static_cast<std::size_t>(r)];
      pairs_.d[e] -= b * gm[static_cast<std::size_t>(r)];
      for (std::size_t k = 0; k < L; ++k) pairs_.e[e * G + k] -= b * em[static_cast<std::size_t>(r)][k];
      // d(z^a s1^b s2^c) = a z^(a-1) s1^b s2^c n + ... : each term a product of two offsets along an axis.
      for (std::size_t k = 0; k < 3; ++k) {
        if (ex[k] == 0) continue;
        Exponents sq = ex;
        --sq[k];
        pairs_.e[e * G + L + static_cast<std::size_t>(square_index(sq))] += b * ex[k] / h3 * axes[k];
      }
    }
  }
  return true;
}

// Gauss points (WallQuadrature::Gauss): node i stands for the depths within half a layer step of its own,
// clipped to the wall ([d_i - D/2, d_i + D/2] and [0, t]), and its two Gauss points lie at the slab's centre
// -+ half its width / sqrt 3, as offsets along the wall normal (the direction of growing depth).
// WallQuadrature::GaussCell crosses these with the two-point rule along each of the cell's edges along the
// wall (offsets -+ half the edge / sqrt 3 about the node): 2 x 2 x 2 points, the product rule that integrates
// a cubic exactly over the cell.
void Discretization::place_wall_points(const DiscretizationOptions& opt) {
  using WQ = DiscretizationOptions::WallQuadrature;
  if (opt.wall_quadrature == WQ::Nodes) return;
  const Index n = num_nodes();
  if (!fits_curvature(opt.basis))
    throw InputError(
        "discretization: Gauss points need a basis that fits curvature (quadratic or wall_quadratic): "
        "the linear fit's gradient does not change across a node's cell");
  if (opt.support != DiscretizationOptions::Support::Wall ||
      opt.wall_depths.size() != static_cast<std::size_t>(n) || !(opt.wall_thickness_m > 0.0) ||
      !(opt.wall_layer_spacing_m > 0.0))
    throw InputError(
        "discretization: Gauss points need a wall support with a depth per node, the wall's thickness "
        "and its layer spacing (a geometry of type 'tube' or 'vessel')");
  const bool cell = opt.wall_quadrature == WQ::GaussCell;
  if (cell && opt.wall_cells.size() != static_cast<std::size_t>(n))
    throw InputError(
        fmt::format("discretization: Gauss points over the cell need each node's cell along the wall ({} "
                    "for {} nodes)",
                    opt.wall_cells.size(), n));
  energy_points_ = cell ? 8 : 2;
  const bool mixed = opt.wall_cube && opt.wall_cubics != DiscretizationOptions::WallCubics::Cube;
  if (mixed && !cell)
    throw InputError(
        "discretization: the cubics with a through-wall factor (wall_cubics) need Gauss points over "
        "each node's cell (wall_quadrature 'gauss_cell'): their gradients vary along the wall");
  linear_directions_ = cell ? 3 : 1;
  point_directions_ = linear_directions_ + (mixed           ? static_cast<int>(kSquares.size())
                                            : opt.wall_cube ? 1
                                                            : 0);
  const std::size_t P = static_cast<std::size_t>(energy_points_),
                    G = static_cast<std::size_t>(point_directions_);
  point_offset_.assign(static_cast<std::size_t>(n) * P * G, 0.0);
  point_axes_.resize(static_cast<std::size_t>(n) * G);
  const double t = opt.wall_thickness_m, half_step = 0.5 * opt.wall_layer_spacing_m,
               gauss = 1.0 / std::sqrt(3.0);
  for (Index i = 0; i < n; ++i) {
    const std::size_t ii = static_cast<std::size_t>(i);
    const double d = opt.wall_depths[ii];
    const double lo = std::max(d - half_step, 0.0), hi = std::min(d + half_step, t);
    const double centre = 0.5 * (lo + hi) - d, spread = hi > lo ? 0.5 * (hi - lo) * gauss : 0.0;
    point_axes_[ii * G] = opt.wall_normals[ii];
    for (std::size_t k = static_cast<std::size_t>(linear_directions_); k < G; ++k)
      point_axes_[ii * G + k] = opt.wall_normals[ii];
    std::array<double, 2> half_edge{0.0, 0.0}, along_centre{0.0, 0.0};
    if (cell)
      for (std::size_t k = 0; k < 2; ++k) {
        const Vec3& edge = opt.wall_cells[ii].edges[k];
        const double len = edge.norm();
        if (!(len > 0.0))
          throw InputError(fmt::format("discretization: node {}'s cell has an empty edge along the wall", i));
        point_axes_[ii * G + 1 + k] = edge / len;
        half_edge[k] = 0.5 * len * gauss;
        along_centre[k] = opt.wall_cells[ii].centre[k];
      }
    for (std::size_t q = 0; q < P; ++q) {
      double* o = &point_offset_[(ii * P + q) * G];
      o[0] = (q & 1) ? centre + spread : centre - spread;
      if (cell) {
        o[1] = along_centre[0] + ((q & 2) ? half_edge[0] : -half_edge[0]);
        o[2] = along_centre[1] + ((q & 4) ? half_edge[1] : -half_edge[1]);
      }
      if (mixed) {
        // The products of the point's wall-frame coordinates (add_wall_cubics), from its offset vector.
        const std::size_t L = static_cast<std::size_t>(linear_directions_);
        Vec3 P = Vec3::Zero();
        for (std::size_t k = 0; k < L; ++k) P += o[k] * point_axes_[ii * G + k];
        const Vec3 c(P.dot(point_axes_[ii * G]), P.dot(point_axes_[ii * G + 1]),
                     P.dot(point_axes_[ii * G + 2]));
        for (std::size_t a = 0; a < kSquares.size(); ++a) o[L + a] = monomial(kSquares[a], c);
      } else if (opt.wall_cube) {
        o[G - 1] = o[0] * o[0];  // the cube's direction (add_wall_cube)
      }
    }
  }
}

void Discretization::compute_volumes(const DiscretizationOptions& opt) {
  const Index n = num_nodes();
  const double rho = material_.density_kg_m3;
  V_.assign(n, 0.0);
  tet_volume_ = 0.0;
  for (std::size_t t = 0; t < tets_.size(); ++t) {
    const Tet& T = tets_[t];
    const double v = signed_volume(X_[T[0]], X_[T[1]], X_[T[2]], X_[T[3]]);
    if (!(v > 0.0))
      throw InputError(fmt::format("discretization: virtual tetrahedron {} is inverted or flat", t));
    tet_volume_ += v;
    if (opt.volume != VolumeRule::MuellerKernel)
      for (Index a : T) V_[a] += 0.25 * v;
  }
  if (opt.volume == VolumeRule::Simpson) {
    if (opt.volume_factors.size() != static_cast<std::size_t>(n))
      throw InputError(fmt::format("discretization: the Simpson volume rule has {} factors for {} nodes",
                                   opt.volume_factors.size(), n));
    for (Index i = 0; i < n; ++i) V_[i] *= opt.volume_factors[static_cast<std::size_t>(i)];
  }
  if (opt.volume != VolumeRule::MuellerKernel) {
    for (Index i = 0; i < n; ++i)
      if (!(V_[i] > 0.0))
        throw InputError(
            fmt::format("discretization: node {} belongs to no virtual tetrahedron, so it has no volume "
                        "(tet-partition rule)",
                        i));
  } else {
    // Mueller et al. 2004 (docs/model/04-volumes.md): rbar_i = mean distance to the 10 nearest neighbours,
    // m_i = s rbar_i^3 rho with s normalising the density estimate, V_i = m_i / rho_i.
    std::vector<double> rbar3(n);
    for (Index i = 0; i < n; ++i) {
      std::vector<double> dist;
      for (Index e = pairs_.row_start[i]; e < pairs_.row_start[i + 1]; ++e)
        dist.push_back((X_[pairs_.col[e]] - X_[i]).norm());
      const std::size_t k = std::min<std::size_t>(10, dist.size());
      std::partial_sort(dist.begin(), dist.begin() + static_cast<std::ptrdiff_t>(k), dist.end());
      const double r = std::accumulate(dist.begin(), dist.begin() + static_cast<std::ptrdiff_t>(k), 0.0) /
                       static_cast<double>(k);
      rbar3[i] = r * r * r;
    }
    auto kernel_sum = [&](Index i, const std::vector<double>& q) {
      double s = q[i] * kernels::poly6(0.0, h_[i]);
      for (Index e = pairs_.row_start[i]; e < pairs_.row_start[i + 1]; ++e)
        s += q[pairs_.col[e]] * pairs_.w[e];
      return s;
    };
    double s = 0.0;
    for (Index i = 0; i < n; ++i) s += 1.0 / kernel_sum(i, rbar3);
    s /= n;
    m_.resize(n);
    for (Index i = 0; i < n; ++i) m_[i] = s * rbar3[i] * rho;
    for (Index i = 0; i < n; ++i) V_[i] = m_[i] / kernel_sum(i, m_);
    return;
  }
  m_.resize(n);
  for (Index i = 0; i < n; ++i) m_[i] = rho * V_[i];
}

double Discretization::total_volume() const {
  return std::accumulate(V_.begin(), V_.end(), 0.0);
}

double Discretization::mean_neighbours() const {
  return static_cast<double>(pairs_.col.size()) / static_cast<double>(num_nodes());
}

Eigen::MatrixXd Discretization::fit_residual_operator(Index i, bool quadratic) const {
  // r_ij = y_ij - sum_l y_il q_jl with q_jl = d_il . X_ij (linear: the affine fit's prediction at X_ij) or
  // fit_il . p(X_ij / h_i) (quadratic), y_ij = y_j - y_i: R = (I - Q) [-1 | I].
  const Index K = pairs_.row_size(i);
  const Index e0 = pairs_.row_start[i];
  // The wall-quadratic fit leaves the through-wall square out; the stabiliser on a quadratic fit must still
  // ignore it.
  if (quadratic && basis_ != GradientBasis::Quadratic) return quadratic_residual_operator(i);
  const bool curved = fits_curvature(basis_);
  Eigen::MatrixXd R(K, K + 1);
  for (Index j = 0; j < K; ++j) {
    const Vec3 Xij = X_[static_cast<std::size_t>(pairs_.col[e0 + j])] - X_[static_cast<std::size_t>(i)];
    const Vec9 pj = curved ? fit_monomials(basis_, Xij, h_[i], fit_normal(i)) : Vec9::Zero();
    double row_sum = 0.0;
    for (Index l = 0; l < K; ++l) {
      const double q = curved ? fit_[static_cast<std::size_t>(e0 + l)].dot(pj)
                              : pairs_.d[static_cast<std::size_t>(e0 + l)].dot(Xij);
      const double v = (j == l ? 1.0 : 0.0) - q;
      R(j, 1 + l) = v;
      row_sum += v;
    }
    R(j, 0) = -row_sum;
  }
  return R;
}

Eigen::MatrixXd Discretization::quadratic_residual_operator(Index i) const {
  // The weighted least-squares projection onto the quadratic monomials: with M (K x 9) the monomials p(X_ij /
  // h_i) and W = diag(w_ij), Q = M B^+ M^T W, B = M^T W M. B^+ is a pseudo-inverse (eigenvalues below 1e-10
  // of the largest dropped): on a wall with two layers in the support z^2 is not independent of z, and the
  // projection is then onto what the neighbourhood can represent, still exact for every quadratic field.
  const Index K = pairs_.row_size(i);
  const Index e0 = pairs_.row_start[i];
  Eigen::MatrixXd M(K, 9);
  Eigen::VectorXd w(K);
  for (Index j = 0; j < K; ++j) {
    M.row(j) = quadratic_monomials(
        X_[static_cast<std::size_t>(pairs_.col[e0 + j])] - X_[static_cast<std::size_t>(i)], h_[i]);
    w(j) = pairs_.w[static_cast<std::size_t>(e0 + j)];
  }
  const Mat9 B = M.transpose() * w.asDiagonal() * M;
  Eigen::SelfAdjointEigenSolver<Mat9> es(B);
  const double cut = 1e-10 * es.eigenvalues().cwiseAbs().maxCoeff();
  Vec9 inv = Vec9::Zero();
  for (int k = 0; k < 9; ++k)
    if (es.eigenvalues()(k) > cut) inv(k) = 1.0 / es.eigenvalues()(k);
  const Mat9 Bplus = es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
  const Eigen::MatrixXd IQ = Eigen::MatrixXd::Identity(K, K) - M * Bplus * M.transpose() * w.asDiagonal();
  Eigen::MatrixXd R(K, K + 1);
  R.col(0) = -IQ.rowwise().sum();
  R.rightCols(K) = IQ;
  return R;
}

Mat3 Discretization::displacement_gradient(Index i, const Vec3Array& u, bool eq3_literal_sign) const {
  const Mat3 G = deformation_gradient(i, u);  // the same sum: sum_j (u_j - u_i) d_ij^T
  return eq3_literal_sign ? Mat3(-G) : G;
}

void Discretization::deformation_gradient_derivatives(Index i, const Vec3Array& x, Mat3* D) const {
  const std::size_t G = static_cast<std::size_t>(point_directions_);
  for (std::size_t k = 0; k < G; ++k) D[k].setZero();
  const Vec3 xi = x[i];
  for (Index e = pairs_.row_start[i], end = pairs_.row_start[i + 1]; e < end; ++e) {
    const Vec3 dx = x[pairs_.col[e]] - xi;
    for (std::size_t k = 0; k < G; ++k)
      D[k].noalias() += dx * pairs_.e[static_cast<std::size_t>(e) * G + k].transpose();
  }
}

Mat3 Discretization::deformation_gradient(Index i, const Vec3Array& x) const {
  // sum_j (x_j - x_i) d_ij^T, accumulated column by column in three local vectors: the outer product written
  // as one Eigen expression goes through a stack temporary whose reloads stall store forwarding (2-4x slower,
  // docs/performance.md section 5).
  const Index* col = pairs_.col.data();
  const Vec3* d = pairs_.d.data();
  const Vec3 xi = x[i];
  Vec3 c0 = Vec3::Zero(), c1 = Vec3::Zero(), c2 = Vec3::Zero();
  for (Index e = pairs_.row_start[i], end = pairs_.row_start[i + 1]; e < end; ++e) {
    const Vec3 dx = x[col[e]] - xi;
    c0 += d[e].x() * dx;
    c1 += d[e].y() * dx;
    c2 += d[e].z() * dx;
  }
  Mat3 F;
  F.col(0) = c0;
  F.col(1) = c1;
  F.col(2) = c2;
  return F;
}

}  // namespace vascsim
