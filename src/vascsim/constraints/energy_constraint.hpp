#pragma once
// The paper's "elastic potential energy constraint" of a virtual tetrahedron (Zhang et al. 2021,
// Eqs. 18-24), in two forms (docs/model/16-deviations.md, E11 and E12):
//
//  * the sound per-spring barycentre form (docs/model/16-deviations.md, E11, and
//  docs/model/19-position-based.md section 19.2): one
//    XPBD distance constraint from each vertex to the mass-weighted barycentre, with the barycentre's
//    dependence on all four vertices in the gradient. Momentum-conserving; it represents exactly the
//    energy of Eq. 18, 1/2 sum_a k_a delta_a^2, with compliance alpha_a = 1/k_a (m/N).
//  * the LITERAL form as printed (Eqs. 18-24 with the Eq. 20-23 gradients), KNOWN DEFECTIVE and kept only
//    for the paper_literal pipeline and the negative tests that pin its defects (docs/model/16-deviations.md,
//    E11): the gradients are not those of C, every projection moves all four vertices towards the barycentre
//    (C >= 0), compressed tets are compressed further, Delta x has units of energy, and
//    sum_b m_b Delta x_b != 0.
//
// Tet vertices are indexed 0..3 here (the paper's 1..4).

#include <array>
#include <vector>

#include "vascsim/constraints/xpbd_projection.hpp"

namespace vascsim::constraints {

using TetPositions = std::array<Vec3, 4>;
using TetMasses = std::array<double, 4>;

/// Paper Eq. 19: mass-weighted barycentre x0 = sum_b m_b x_b / M, M = sum_b m_b.
Vec3 mass_weighted_barycentre(const TetPositions& x, const TetMasses& m);

/// Rest distances d_a0 = |X_a - X0| of the four vertices to the rest barycentre (m).
std::array<double, 4> barycentre_rest_distances(const TetPositions& X, const TetMasses& m);

/// Per-spring barycentre constraint of vertex a (docs/model/16-deviations.md, E11):
///   C_a(x) = |x_a - x0(x)| - d_a0,   x0 = sum_b m_b x_b / M                             (m)
///   grad_b C_a = (delta_ab - m_b/M) n_a,   n_a = (x_a - x0)/|x_a - x0|
/// sum_b grad_b C_a = 0 (translation invariance), so the XPBD correction conserves momentum exactly.
/// Masses are the physical masses used for the barycentre (also for fixed vertices; their w = 0 is
/// passed to the projection separately). n_a = 0 when x_a coincides with x0 (projection skipped).
ScalarConstraint<4> barycentre_spring_constraint(const TetPositions& x, const TetMasses& m, int a,
                                                 double rest_distance);

/// Closed form of sum_b w_b |grad_b C_a|^2 = 1/m_a - 1/M for the per-spring constraint
/// (docs/model/16-deviations.md, E11), valid when all four vertices are free (w_b = 1/m_b). Use it with
/// xpbd_delta_lambda:
///   Delta lambda_a = (-C_a - alpha~_a lambda_a) / (1/m_a - 1/M + alpha~_a).
double barycentre_spring_denominator(const TetMasses& m, int a);

/// Equal spring stiffness k_a = k calibrated on pure dilation, sum_a k_a d_a0^2 = 9 kappa V_T
/// (docs/model/16-deviations.md, E11, [derived]); kappa bulk modulus (Pa), V_T rest volume (m^3). Returns k
/// in N/m; the XPBD compliance is 1/k. Shear stays under-resisted (rank 4 of 6).
double barycentre_spring_stiffness(double bulk_modulus_pa, double rest_volume_m3,
                                   const std::array<double, 4>& rest_distances);

/// Rest data of the four barycentre springs of one tet: rest distances (m) and the equal stiffness calibrated
/// on dilation with barycentre_spring_stiffness (N/m).
struct BarycentreSprings {
  std::array<double, 4> rest_distances{};
  double stiffness = 0.0;
};
BarycentreSprings barycentre_springs(const TetPositions& X, const TetMasses& m, double bulk_modulus_pa);

/// barycentre_springs of every tetrahedron of a mesh: rest positions X (m), tets as four node indices, nodal
/// masses (kg), bulk modulus (Pa). One entry per tet, in order.
std::vector<BarycentreSprings> barycentre_springs_of_mesh(const Vec3Array& X,
                                                          const std::vector<std::array<Index, 4>>& tets,
                                                          const std::vector<double>& masses,
                                                          double bulk_modulus_pa);

/// LITERAL energy constraint as printed, KNOWN DEFECTIVE (docs/model/16-deviations.md, E11):
///   Eq. 18:    C = 1/2 sum_a k_a (|x_a - x0| - d_a0)^2      (J when k_a is in N/m)
///   Eq. 19:    x0 = sum_b m_b x_b / M
///   Eqs. 20-23: "grad"_b C = n_b = (x_b - x0)/|x_b - x0|      (NOT the gradient of C: no k_b delta_b
///              factor and no barycentre term)
/// Projected with pbd_project (Eq. 12) this gives Eq. 24, Delta x_b = -k' w_b C n_b / sum_a w_a, which
/// points inward for every vertex of a stretched or a compressed tet alike and does not conserve momentum.
/// Guarded like every projection by kDenominatorEpsilon.
ScalarConstraint<4> literal_energy_constraint(const TetPositions& x, const TetMasses& m,
                                              const std::array<double, 4>& k,
                                              const std::array<double, 4>& rest_distances);

}  // namespace vascsim::constraints
