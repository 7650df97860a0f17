#pragma once
// `quasi_static`: static equilibrium at each load step by minimising the total potential
// Pi(x) = U(x) - f_ext . x over the free nodes (docs/model/00-design-decisions.md, decision 4;
// docs/model/13-quasi-static-solver.md). Truncated Newton: the Newton system H dx = r is solved by
// preconditioned conjugate gradients on analytic Hessian-vector products, with the linear-elastic stiffness
// of the virtual tetrahedra (incomplete or exact Cholesky, factorised once) as the preconditioner; negative
// curvature stops CG early; a backtracking Armijo line search on Pi globalises. A load step starts from a
// linear predictor that carries the prescribed increment into the free nodes, then a secant extrapolation
// along the load path. Converged when |r_free| <= tol * max(|reactions|, |f_ext|).
//
// The problem's tools (the catheter) are frictionless one-sided contacts by an active set: a node that enters
// a tool is put on its surface and its normal degree of freedom is held there (the residual, the CG
// directions and the preconditioned vectors are filtered by I - n n^T, the "modified PCG" of Baraff & Witkin
// 1998), so it can still slide along the tool. After Newton converges, a contact whose normal reaction lambda
// = -r.n pulls on the tool (lambda < 0) is released and Newton continues; the step ends when no node
// penetrates and no contact pulls. The tool force is sum lambda n over its contacts.
//
// Driven by a device (DeviceDrivenModel), every frame solves the equilibrium at the posed tools with the
// other loads at full value (load factor 1); frame_s is the simulated time a frame stands for.

#include <memory>
#include <optional>

#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/model/equilibrium_preconditioner.hpp"
#include "vascsim/model/meshless_factor.hpp"
#include "vascsim/model/newton_equilibrium.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/model/tool_placement.hpp"

namespace vascsim {

struct QuasiStaticSettings {
  int load_steps = 10;              ///< equal load increments to s = 1
  double rel_tolerance = 1e-8;      ///< relative force residual at convergence
  int max_newton_iterations = 60;   ///< per load step
  int max_cg_iterations = 2000;     ///< per Newton iteration
  bool fail_on_divergence = false;  ///< throw instead of reporting a load step that did not converge
  /// "meshless" (default: a supernodal Cholesky factor of the assembled meshless Hessian,
  /// meshless_factor.hpp, refactored at the converged state of a load step whose Newton iterations needed
  /// more than refactor_cg_iterations CG iterations on average), or a factor of the virtual tets' linear
  /// stiffness: "cholesky" (exact; its fill grows fast: 21 M nonzeros and 90 ms per solve at 23k nodes),
  /// "incomplete_cholesky" (cheap at any size); "auto" picks one of these two by size (10,000 free nodes);
  /// "none".
  std::string preconditioner = "meshless";
  int refactor_cg_iterations = 10;  ///< meshless: refactor after a load step that averaged more CG per Newton
  int max_contact_passes = 50;      ///< active-set changes after a converged Newton solve, per load step
  double frame_s = 1e-3;            ///< simulated time per frame when a device drives the model, s
};

/// Reads the `quasi_static` block of a scene (docs/scene-format.md).
QuasiStaticSettings read_quasi_static_settings(JsonReader& block);

/// The registry entry (registry.cpp).
ModelEntry quasi_static_model_entry();

class QuasiStaticModel final : public Model, public DeviceDrivenModel {
 public:
  QuasiStaticModel(const Problem& problem, const QuasiStaticSettings& settings);
  std::string name() const override { return "quasi_static"; }
  int num_steps() const override { return settings_.load_steps; }
  StepReport advance(int k) override;
  const Vec3Array& positions() const override { return x_; }
  double load_factor() const override { return s_; }
  nlohmann::json info() const override;
  /// Per tool at the last solve: sum lambda n over its contacts (force on the tissue), the moment about
  /// its tool point, the contact count.
  std::vector<ObstacleLoad> obstacle_loads() const override { return obstacle_load_; }
  DeviceDrivenModel* device_driven() override { return this; }

  // DeviceDrivenModel: a frame is the equilibrium at the posed tools (load factor 1).
  void set_tool_pose(std::size_t tool, const Vec3& position_m,
                     const Eigen::Quaterniond& orientation) override;
  StepReport step() override;
  double time() const override { return t_; }
  double frame_length_s() const override { return settings_.frame_s; }
  std::vector<ObstacleLoad> tool_loads() const override { return obstacle_load_; }

  /// Solves for equilibrium at load factor s starting from the current state (also used by experiments).
  StepReport solve(double s);
  // solve(s) from load factor s_from; an equilibrium with inverted material (model/inversion_check.hpp) is
  // undone and s reached in two half steps, at most kMaxHalvings deep, then a NumericalError.
  StepReport solve_without_inversion(double s_from, double s, int depth);

 private:
  // One load step, in the order solve() runs them.
  void predict(double s, const Vec3Array& f_ext, StepReport& rep);
  void finish_step(double s, double res, StepReport& rep);
  void place_tools(double s);  // the contact geometry at load factor s (or the device poses)

  const Problem& problem_;
  QuasiStaticSettings settings_;
  Vec3Array x_, x_prev_;  // current and previous converged states (secant predictor)
  double s_ = 0.0, s_prev_ = 0.0, t_ = 0.0;
  FreeDofs free_;
  ContactActiveSet contacts_;
  std::optional<EmbeddedContact> embedded_;  // the tools meet the wall's surface (problem.contact_surface())
  ToolPlacement tools_;
  NewtonEquilibrium newton_;
  std::unique_ptr<EquilibriumPreconditioner> preconditioner_;
  MeshlessFactor* meshless_ = nullptr;  // preconditioner_ when it is the meshless factor
  int refactorisations_ = 0;
  bool final_load_step_ = false;  // advance() is solving the last load step (no refactorisation after it)
  std::vector<ObstacleLoad> obstacle_load_;
  long long contact_passes_ = 0;
  long long total_newton_ = 0, total_cg_ = 0;
  int unconverged_steps_ = 0;
};

}  // namespace vascsim
