#pragma once
// `tensor_mass`: the tetrahedral tensor-mass model of
//   S. X. Guo, X. J. Cai, B. F. Gao, "A tensor-mass method-based vascular model and its performance
//   evaluation for interventional surgery virtual reality simulator", Int. J. Medical Robotics and Computer
//   Assisted Surgery 14(6), e1946, 2018 (the paper's baseline [26]),
// which is linear (small-strain) P1 finite elements with the stiffness stored on the mesh's vertices and
// edges (S. Cotin, H. Delingette, N. Ayache, "A hybrid elastic model for real-time cutting, deformations, and
// force feedback for surgery training and simulation", The Visual Computer 16(8), 2000), integrated by
// implicit Euler with conjugate gradients as in the group's earlier triangular model.
// docs/model/25-baselines.md section 25.4.
//
// Per tet T (rest volume V_T, shape gradients g_a): K^T_ab = V_T (lambda g_a g_b^T + mu g_b g_a^T + mu
// (g_a.g_b) I) (tet_stiffness.hpp), summed into a vertex tensor K_ii per node and an edge tensor K_ij per
// edge (the 3x3 blocks of one sparse matrix); f_i = -K_ii u_i - sum_j K_ij u_j, lambda and mu from the
// scene's E and nu. Per frame h:
//   (M + h D + h^2 K) dv = h (f - h K v - D v),  D = alpha M + beta K (Rayleigh),  v += dv,  x += h v,
// solved matrix-free by Jacobi-preconditioned CG with the tensors; prescribed nodes and tool contacts enter
// as filtered degrees of freedom (Baraff & Witkin 1998's modified PCG, contact_active_set.hpp). Not rotation
// invariant, faithfully: large rotations inflate it.

#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/dynamic_baseline.hpp"

#include <Eigen/SparseCore>

namespace vascsim {

struct TensorMassSettings {
  BaselineFrames frames;
  double rayleigh_mass_per_s = 0.0;    ///< alpha, 1/s
  double rayleigh_stiffness_s = 1e-4;  ///< beta, s
  double cg_tolerance = 1e-8;  ///< CG stops at this residual relative to the free rows' right-hand side
  int max_cg_iterations = 500;
};

TensorMassSettings read_tensor_mass_settings(JsonReader& block);
ModelEntry tensor_mass_model_entry();

class TensorMassModel final : public DynamicBaseline {
 public:
  TensorMassModel(const Problem& problem, const TensorMassSettings& settings);
  /// out = K in (all nodes), N.
  void apply_stiffness(const Vec3Array& in, Vec3Array& out) const;

 protected:
  StepReport frame(double s_prev, double s_next) override;
  nlohmann::json method_info() const override;

 private:
  void apply_system(const Vec3Array& p, Vec3Array& out) const;  // (M + h D + h^2 K) p
  int solve(const Vec3Array& b, Vec3Array& dv);                 // filtered PCG from dv; returns iterations
  TensorMassSettings settings_;
  FreeDofs free_;
  ContactActiveSet contacts_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> K_;
  std::vector<double> mass_, diag_;  // diag_: the Jacobi preconditioner per dof (3 per node)
  Vec3Array u_, f_, Kv_, rhs_, dv_, r_, z_, p_, Ap_;
  long long cg_total_ = 0;
  int last_cg_ = 0;
};

}  // namespace vascsim
