#pragma once
// Meshless strain constraint per node (docs/model/19-position-based.md (A)): the point-primitive SVK strain
// energy of node i, U_i = V_i [mu E_i:E_i + lambda/2 tr(E_i)^2] (docs/model/07-strain-stress-energy.md, the
// paper's Eqs. 2-7 with the E1/E2 fixes), written as one 6-component XPBD constraint so the real-time model
// is still the paper's energy:
//   c_i = Mandel(E_i) = (E_00, E_11, E_22, sqrt2 E_12, sqrt2 E_02, sqrt2 E_01)      (dimensionless)
//   E_i = 1/2 (F_i^T F_i - I),  F_i = sum_{k in N_i u {i}} x_k d_ik^T   (docs/model/06-gradients.md, d_ii =
//   -sum_j d_ij) U_i = 1/2 c_i^T (V_i C^) c_i,  C^ = lambda e e^T + 2 mu I_6,  e = (1,1,1,0,0,0)^T   (exact,
//   Pa) compliance alpha_i = (V_i C^)^{-1}  (1/J) J_ik = dc_i/dx_k (6x3),  dE_pq/dx_k = 1/2 (d_ik,q F_:,p +
//   d_ik,p F_:,q)  (sqrt2 on the shear rows)
// Projection (xpbd_block_project): Delta lambda = -(J W J^T + alpha~)^{-1} (c + alpha~ lambda),
// Delta p_k = w_k J_ik^T Delta lambda, alpha~ = alpha_i / h^2 (Macklin et al. 2016 in block form).
// Because sum_k d_ik = 0, sum_k J_ik = 0 and the correction conserves momentum.
//
// The zero-energy-mode stabiliser (docs/model/09-volume-term-and-stabiliser.md section 9.2) is not part of
// this constraint.

#include <span>
#include <vector>

#include "vascsim/constraints/xpbd_projection.hpp"

namespace vascsim::constraints {

/// Evaluation of the constraint of one node. Buffers are reused across calls (no allocation once grown).
struct MeshlessStrainEval {
  Mat3 F = Mat3::Identity();  ///< F_i
  Vec6 c = Vec6::Zero();      ///< Mandel(E_i)
  std::vector<Index> nodes;   ///< the stencil: nodes[0] = i, then the neighbours in pair-table order
  std::vector<Mat63> J;       ///< J[s] = dc_i / dx_{nodes[s]}, 1/m
};

/// Mandel vector of a symmetric 3x3 tensor: (A_00, A_11, A_22, sqrt2 A_12, sqrt2 A_02, sqrt2 A_01), so that
/// A:B = mandel(A) . mandel(B).
Vec6 mandel(const Mat3& A);

/// Inverse of mandel(): the symmetric tensor L with mandel(L) = v.
Mat3 unmandel(const Vec6& v);

/// The 6x6 matrix J W J^T = sum_k w_k J_ik J_ik^T of node i's constraint in closed form, from C = F_i^T F_i
/// and D_i = sum_k w_k d_ik d_ik^T (k over the stencil {i} u N_i; D is constant during a run):
///   J_ik^T e_r = F L_r d_ik (L_r = unmandel(e_r), from d(E:L)/dx_k = F L d_k), so
///   (J W J^T)_rs = sum_k w_k d_k^T L_r C L_s d_k = tr(L_r C L_s D)                     [derived]
/// This replaces K+1 products of 6x3 blocks per projection by twelve 3x3 products. Units 1/(kg m^2), those of
/// sum_k w_k |grad_k c|^2 (d in 1/m, w in 1/kg).
Mat6 meshless_strain_block(const Mat3& C, const Mat3& D);

/// C^ = lambda e e^T + 2 mu I_6 (Pa): psi = 1/2 c^T C^ c for c = mandel(E).
Mat6 svk_mandel_stiffness(double lame_lambda_pa, double shear_modulus_pa);

/// alpha_i = (V_i C^)^{-1} = 1/(2 mu V_i) (I - lambda/(3 lambda + 2 mu) e e^T), 1/J.
Mat6 meshless_strain_compliance(double lame_lambda_pa, double shear_modulus_pa, double volume_m3);

/// U_i = 1/2 V_i c^T C^ c, J.
double meshless_strain_energy(const Vec6& c, double lame_lambda_pa, double shear_modulus_pa,
                              double volume_m3);

/// Value c_i and Jacobian J_ik of node i's strain constraint. `neighbours` and `d` are row i of
/// Discretization::pairs() (col and d, same length), `d_self` = self_d()[i], `x` the current positions.
void meshless_strain_constraint(Index i, std::span<const Index> neighbours, std::span<const Vec3> d,
                                const Vec3& d_self, const Vec3Array& x, MeshlessStrainEval& out);

}  // namespace vascsim::constraints
