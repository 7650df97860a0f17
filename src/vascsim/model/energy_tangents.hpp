#pragma once
// The per-node material tangents of the point-primitive energy (docs/model/10-hessian-product.md): for node i
// (and each of its energy points q), the 9 x 9 matrix
//     C_iq = (V_i / points) d^2 psi / dF^2 (F_iq)   [+ the volume term k_v],   N m,
// the second derivative of the point's strain energy with respect to its deformation gradient. Every
// assembled form of the Hessian is built from them: node i's stencil S_i = {i} + N_i couples nodes k, l of
// S_i by the block
//     H_kl^(i) [a][b] = sum_{c,d} C_i[(a,c),(b,d)] d_ik[c] d_il[d]
// (energy_hessian.hpp assembles the whole matrix; wall_multigrid.hpp its diagonal, a window of it and its
// Galerkin coarse form).

#include <Eigen/StdVector>
#include <vector>

#include "vascsim/model/point_primitive_energy.hpp"

namespace vascsim {

using Mat9Array = std::vector<Mat9, Eigen::aligned_allocator<Mat9>>;

/// How a tangent is made positive semi-definite (SVK under compression is indefinite, and a preconditioner
/// must be positive definite).
enum class TangentProjection {
  None,      ///< the exact tangent
  Spectral,  ///< its negative eigenvalues set to zero (a 9 x 9 eigendecomposition where it is indefinite)
  /// the geometric stiffness's stress clamped to its positive part, S -> S+ in dF S + F dS (the built-in SVK
  /// law with the Green strain and no volume term only; otherwise Spectral): the same positive form as the
  /// single-precision Newton operator's (single_precision_hessian.hpp), at a 3 x 3 eigendecomposition
  ClampedStress
};

/// ClampedStress where the energy allows it (the law SinglePrecisionHessian supports), otherwise Spectral.
TangentProjection positive_projection(const PointPrimitiveEnergy& energy);

/// Fills out[i * points + q] for every energy point q of the nodes in `nodes` (null: every node) at
/// configuration x (m), symmetrised and projected as `projection` says. `out` is resized to all nodes'
/// points; entries of other nodes are left as they were. Parallel over nodes (OpenMP) when there are many.
void energy_tangents(const PointPrimitiveEnergy& energy, const Vec3Array& x, TangentProjection projection,
                     Mat9Array& out, const std::vector<Index>* nodes = nullptr);

/// The 3 x 3 block sum_{c,d} C[(a,c),(b,d)] dk[c] dl[d] (a, b the block's row and column): how node l's
/// displacement moves node k's force through one point's tangent C. N/m for C in N m and d in 1/m.
Mat3 tangent_block(const Mat9& C, const Vec3& dk, const Vec3& dl);

}  // namespace vascsim
