#pragma once
// The point-primitive Hessian-vector product in single precision, for the real-time solver's conjugate
// gradients and its preconditioner's smoothing (docs/model/24-implicit.md section 24.1), where a frame's
// linear solves need a relative accuracy of 1e-1 to 1e-3, far above float's 1e-7.
//
// Why: the product is the unit of a frame's cost (each conjugate-gradient iteration with the wall multigrid
// takes three: CG's own, and two in the smoothing form, without the stabiliser's 2-hop matrix, which is about
// half of a product's work). Its arrays stay in cache (the pairs take 16 bytes, the stabiliser's 2-hop matrix
// 8 per entry, the per-node F_i, S_i 72 bytes), so its speed is the instructions per pair: vectors are padded
// to four floats and every update, the per-node 3 x 3 algebra included, is a sum of 4-wide column operations
// (on the real-time vein 0.86 ms a product on one thread instead of 1.50 with 3-float vectors;
// docs/performance.md, "Real time at hand speed").
//
// Same mathematics as PointPrimitiveEnergy::hessian_product (docs/model/10-hessian-product.md), for the
// energies it supports: the built-in St Venant-Kirchhoff law with the Green strain (no material law, no
// volume term), one energy point per node, and a stabiliser that is off or applied as its matrix
// (StabilizerMatrix; the folded linear-fit stabiliser is applied through its matrix here). Parallel over
// nodes with OpenMP.

#include <Eigen/Core>
#include <vector>

#include "vascsim/model/point_primitive_energy.hpp"

namespace vascsim {

/// Which matrix SinglePrecisionHessian::product applies.
enum class ProductForm {
  Exact,     ///< K(x), the energy's Hessian
  Positive,  ///< K(x) with the geometric part's stress clamped to its positive part (semi-definite)
  /// Positive without the stabiliser: the matrix a multigrid smooths with (its V-cycle stays symmetric
  /// whatever matrix it smooths with; the stabiliser's 2-hop couplings, about half a product's work, are
  /// weak beside the elastic ones, and its window and line blocks keep them).
  Smoothing,
};

class SinglePrecisionHessian {
 public:
  /// Whether `energy` is one this product reproduces.
  static bool supports(const PointPrimitiveEnergy& energy);
  /// Copies the discretisation's pairs and the stabiliser in float. Throws std::invalid_argument when
  /// !supports(energy).
  explicit SinglePrecisionHessian(const PointPrimitiveEnergy& energy);

  /// F_i and the SVK stress S_i at configuration x (m), for the products and the forces that follow. A call
  /// at the very state of the last one (bit for bit) does nothing: a Newton step's residual and its conjugate
  /// gradients linearise at the same state.
  void linearize(const Vec3Array& x);
  /// The internal forces f = -dU/dx (N, every node) at the last linearize's configuration, in float: the
  /// products' second pass with the stress V_i F_i S_i (computed in double, rounded once) and the
  /// stabiliser's matrix on the displacement x - X. Relative accuracy about 1e-6 of the forces in play
  /// (float's rounding of each term, not of the positions), for residuals judged at a tolerance of 1e-4 or
  /// looser: the real-time frames' (docs/model/24-implicit.md, "Forces in single precision"). About the
  /// double forces' cost; what it saves is the linearisation the products then share.
  void forces(Vec3Array& f) const;
  /// out = K(x) v (N for v in m; K the energy's Hessian at the last linearize, stabiliser included), every
  /// node. ProductForm::Positive: the geometric part dF S uses S with its negative eigenvalues set to zero:
  /// K is then positive semi-definite at any state (the material part F dS always is; dF S is where
  /// compression makes SVK indefinite), as a multigrid's smoothing needs; Smoothing: that without the
  /// stabiliser.
  void product(const Vec3Array& v, Vec3Array& out, ProductForm form = ProductForm::Exact) const;

 private:
  struct Pair {
    Index node;
    float d[3];
  };
  using Mat43f = Eigen::Matrix<float, 4, 3>;
  /// Pass 2 at node k: Q_k d_kk + sum_{i: k in N_i} Q_i d_ik, plus the stabiliser's sum_c K_kc (v_c - v_k)
  /// unless v is null.
  Eigen::Vector4f gather(Index k, const std::vector<Mat43f>& Q, const std::vector<Eigen::Vector4f>* v) const;

  const PointPrimitiveEnergy& energy_;
  float lambda_ = 0.f, mu_ = 0.f;
  std::vector<Index> row_start_, trow_start_;
  std::vector<Pair> pairs_, transposed_;
  std::vector<Eigen::Vector3f> self_d_;
  std::vector<float> volume_;
  // The stabiliser's scalar matrix, row-major (its rows sum to zero: applied to differences).
  std::vector<Index> stab_start_, stab_col_;
  std::vector<float> stab_value_;
  // Per node: F_i and S_i (linearize), and the product's intermediate dP_i.
  std::vector<Eigen::Matrix3f> S_, S_plus_;
  std::vector<Mat43f> Fc_, Ft_;     // F and F^T padded to four rows, for the product
  std::vector<Mat43f> P_;           // V F S padded, for the forces
  std::vector<Eigen::Vector4f> u_;  // x - X padded, for the stabiliser's forces
  Vec3Array x_;                     // the state of the last linearize
  // (padded to four rows: the product's updates are 4-wide).
  mutable std::vector<Mat43f> Q_;
  mutable std::vector<Eigen::Vector4f> v_;
};

}  // namespace vascsim
