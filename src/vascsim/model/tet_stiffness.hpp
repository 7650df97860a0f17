#pragma once
// Linear-elastic P1 stiffness of the virtual tetrahedra (docs/model/25-baselines.md, tensor-mass row):
// K^T_jk = V_T (lambda g_j g_k^T + mu g_k g_j^T + mu (g_j . g_k) I). Used as the preconditioner of the
// quasi-static Newton-CG solver: it discretises the same elasticity operator as the meshless model,
// so (factorised exactly) it is spectrally close to the meshless Hessian at small strain.

#include <Eigen/SparseCore>

#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

/// 3N x 3N stiffness (N/m) of the tets over rest positions X with Lame constants lambda, mu (Pa).
Eigen::SparseMatrix<double> linear_tet_stiffness(const Vec3Array& X, const std::vector<Tet>& tets,
                                                 double lambda, double mu);

}  // namespace vascsim
