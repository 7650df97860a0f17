#pragma once
// Elastic energy, forces and Hessian-vector products of the point-primitive (meshless) model,
// docs/model/ sections 6-9: SVK strain energy per node (sound) or Mueller's no-1/2 strain (paper literal),
// Mueller's volume term k_v and the zero-energy-mode stabiliser alpha_hg. Forces are assembled in the
// gather form of docs/model/08-forces.md (two passes over nodes, no atomics), parallel over nodes with
// OpenMP.

#include <memory>
#include <vector>

#include "vascsim/model/discretization.hpp"
#include "vascsim/model/materials/hyperelastic_law.hpp"

namespace vascsim {

class StabilizerMatrix;

enum class StrainMeasure {
  GreenHalf,     ///< E = 1/2 (F^T F - I): SVK, sound (default)
  MuellerNoHalf  ///< eps = F^T F - I (Eq. 5 as printed): 4x stiffer than the E entered (paper literal)
};

/// The fit whose residuals the zero-energy-mode stabiliser penalises.
enum class StabilizerFit {
  Basis,     ///< the gradient's fit (discretization.basis)
  Quadratic  ///< a quadratic fit over the same neighbourhood, whatever the basis
};

struct EnergyOptions {
  StrainMeasure strain = StrainMeasure::GreenHalf;
  double volume_stiffness_pa = 0.0;  ///< k_v of docs/model/09-volume-term-and-stabiliser.md section 9.1 (0 <=
                                     ///< k_v; lambda is reduced by k_v to keep E, nu)
  double stabilizer_alpha =
      0.1;  ///< alpha_hg of docs/model/09-volume-term-and-stabiliser.md section 9.2 (0 disables)
  /// The strain-energy law psi(F) (model/materials/). Null: the built-in SVK of the Material's E and nu
  /// (the default, and the only one the literal strain applies to). With a law, the small-strain moduli of
  /// the law set lambda and mu for the stabiliser and the preconditioner.
  std::shared_ptr<const materials::HyperelasticLaw> law;
  /// Per node, for laws that need one (hgo): the wall's axial/circumferential/radial frame at rest.
  std::vector<materials::MaterialFrame> frames;
  /// Whose residuals the stabiliser penalises (docs/model/09-volume-term-and-stabiliser.md section 9.3): the
  /// gradient's own fit (Basis), or a quadratic fit over the same neighbourhood (Quadratic), which leaves
  /// every quadratic field, bending among them, to the strain energy.
  StabilizerFit stabilizer_fit = StabilizerFit::Basis;
};

/// Energy terms, J.
struct EnergyBreakdown {
  double strain = 0.0;      ///< sum_i V_i psi_i
  double volume = 0.0;      ///< sum_i 1/2 k_v V_i (det F_i - 1)^2
  double stabilizer = 0.0;  ///< sum_i c_i/2 sum_j w_ij |r_ij|^2
  double total() const { return strain + volume + stabilizer; }
};

class PointPrimitiveEnergy {
 public:
  PointPrimitiveEnergy(const Discretization& disc, const EnergyOptions& options);

  const Discretization& discretization() const { return disc_; }
  const EnergyOptions& options() const { return opt_; }
  /// Lame lambda used by the strain term (lambda - k_v), Pa.
  double strain_lambda() const { return lambda_; }
  double shear_modulus() const { return mu_; }
  /// Stabiliser coefficient per node, c_i = alpha_hg mu V_i / tr(A_i), N m^2 (c_i w_ij is a pair stiffness in
  /// N/m; docs/model/09-volume-term-and-stabiliser.md section 9.2): node i's stabiliser energy is c_i/2 sum_j
  /// w_ij |r_ij|^2. All zero when alpha_hg = 0.
  const std::vector<double>& stabilizer_coefficients() const { return stab_c_; }

  /// The stabiliser as a constant matrix when the energy applies it so (a fit other than the linear basis's);
  /// null when it is folded into the stress gather or off.
  const StabilizerMatrix* stabilizer_matrix() const { return stab_matrix_.get(); }

  /// Elastic energy of configuration x (#N positions, m), J.
  EnergyBreakdown energy(const Vec3Array& x) const;

  /// Internal elastic forces f = -dU/dx (N) into `forces` (resized). Returns the total energy, J; without
  /// `with_energy`, NaN, and the stabiliser's matrix is applied without its energy sum (a fifth less time
  /// for the forces of the real-time vein: residuals need no energy).
  double forces(const Vec3Array& x, Vec3Array& forces, bool with_energy = true) const;

  /// Per-node state a Hessian-vector product needs at a fixed configuration: F_i and the stress
  /// S_i (SVK) or sigma_i (literal), per energy point (index i * points + q, Discretization::energy_points).
  /// Built once per Newton iteration, reused by every CG iteration.
  struct Linearization {
    std::vector<Mat3> F, S;
  };
  Linearization linearize(const Vec3Array& x) const;

  /// The MLS deformation gradient F_i of node i in configuration x (1 at rest): det F_i <= 0 is an inverted
  /// node.
  Mat3 deformation_gradient(Index i, const Vec3Array& x) const {
    Vec3 weighted_sum;
    double weighted_squares = 0.0;
    return gradient_and_moments(i, x, weighted_sum, weighted_squares);
  }

  /// Hessian-vector product: out = (d^2 U / dx^2)(x) v, N per m of v. Exact (analytic) for every term.
  void hessian_product(const Vec3Array& x, const Vec3Array& v, Vec3Array& out) const;
  void hessian_product(const Linearization& lin, const Vec3Array& v, Vec3Array& out) const;

 private:
  // Pass 1 of docs/model/08-forces.md for one node (or one of its points, volume V): V P (+ volume term), and
  // the energy.
  Mat3 weighted_stress(Index i, const Mat3& F, double V, EnergyBreakdown* e) const;
  // Stress S (SVK) or sigma (literal) of F, Pa.
  Mat3 stress(const Mat3& F) const;
  // Directional derivative of weighted_stress at F (with stress S) along dF.
  Mat3 weighted_stress_derivative(Index i, const Mat3& F, const Mat3& S, const Mat3& dF, double V) const;
  // Pass 1 for node i: sum_j (y_j - y_i) d_ij^T, with sum_j w_ij (y_j - y_i) and sum_j w_ij |y_j - y_i|^2.
  Mat3 gradient_and_moments(Index i, const Vec3Array& y, Vec3& weighted_sum, double& weighted_squares) const;
  // Pass 2: the stress gather with the stabiliser folded in (point_primitive_energy.cpp).
  void folded_gather(const std::vector<Mat3>& Q, const std::vector<Mat3>* R, const Vec3Array& own,
                     const Vec3Array& y, Vec3Array& out) const;
  void add_point_stress(Index i, int q, const Mat3& P, Mat3& Q, Mat3* R) const;
  struct Workspace {
    std::vector<Mat3> Q;  // Ptilde_i - c_i F_i A_i (or its derivative)
    std::vector<Mat3>
        R;          // Gauss points: sum_q o_qk Ptilde_q per node and direction k, conjugate to dF_i/du_k
    Vec3Array own;  // c_i sum_j w_ij (y_j - y_i)
    Vec3Array u;    // x - X (the stabiliser matrix's argument)
  };
  static Workspace& workspace(Index n);
  double stabilizer_energy(const std::vector<Mat3>& F, const Vec3Array& x) const;

  const Discretization& disc_;
  EnergyOptions opt_;
  double lambda_, mu_;
  std::vector<double> stab_c_;   // c_i = alpha_hg mu V_i / tr(A_i), N/m * m^3
  std::vector<Mat3> stab_cA_;    // c_i A_i, N/m
  std::vector<double> stab_cw_;  // c_i w_ik per transposed pair (row k), N/m
  bool folded_stab_ = false;     // the stabiliser folded into the stress gather (linear basis)
  std::shared_ptr<const StabilizerMatrix>
      stab_matrix_;  // the stabiliser as a constant matrix (quadratic basis)
};

}  // namespace vascsim
