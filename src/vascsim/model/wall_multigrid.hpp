#pragma once
// The real-time model's preconditioner on a wall lattice (docs/model/24-implicit.md section 24.1): a
// two-level method whose application costs about two Hessian products and whose parts are refreshed at the
// rates their accuracy needs, instead of a sparse Cholesky factor of the whole Hessian (nnz(L) 1.9e7 on the
// 0.3 mm vein: 7-9 ms per solve, about a second per refactorisation, and stale a few tenths of a millimetre
// after the tool moves).
//
// Three parts, for the Newton matrix H = K(x) + M/h^2 on the free nodes:
// - the coarse level: every second column and cross-section of the wall lattice with all its layers
//   (wall_coarse_space.hpp), its Galerkin operator A_c = P^T H P (galerkin_hessian.hpp) and a sparse Cholesky
//   factor of it (a sixteenth of the fine factor's size: 0.4 ms per solve). It carries the wall's global
//   response (bending and ovalisation over the whole vessel), which changes slowly: refreshed in the
//   background;
// - an exact window round the tools: the nodes within a couple of node spacings of a tool's surface, where
//   the contact and the strain change from frame to frame, solved with a dense Cholesky factor of H's block
//   there (in float) built at every frame's start, with the contacts' normal constraints (a Woodbury
//   correction on that factor);
// - damped line Jacobi on the other nodes: one block per through-wall line (a lattice column's layers at one
//   cross-section), with the blocks of the last refresh. The wall is stiffer across its thickness than along
//   it, and a node's own 3 x 3 block left that coupling to the coarse level: the lines took 20 % fewer CG
//   iterations on the real-time vein under a random hand (2,817 against 3,513 in 301 lockstep frames).
//   The window takes whole lines, so none is split.
// Applied as one symmetric V-cycle, smooth - coarse - smooth, with a matrix close to the Newton matrix for
// the two residuals (set_operator: the solver's, in the smoothing form of single_precision_hessian.hpp,
// without the stabiliser). The cycle is symmetric whatever symmetric matrix it smooths with, so conjugate
// gradients stay exact whatever the refresh state: on the 0.3 mm vein pressed at 5 mm/s, 4-6 iterations per
// Newton step with every part fresh, 5-8 with the coarse level 0.1-0.2 s old.
//
// Only for walls whose nodes form a lattice (tubes and swept vessels) with one energy point per node; other
// bodies keep the Cholesky factor (meshless_factor.hpp).

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <memory>

#include "vascsim/core/dense_cholesky.hpp"
#include "vascsim/core/sparse_cholesky.hpp"
#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/embedded_contact.hpp"
#include "vascsim/model/energy_tangents.hpp"
#include "vascsim/model/equilibrium_preconditioner.hpp"
#include "vascsim/model/galerkin_hessian.hpp"

namespace vascsim {

struct WallMultigridOptions {
  double inv_h2 = 0.0;  ///< the inertia shift M/h^2 (1/s^2); 0 for a static solve
  double window_spacings =
      2.0;                      ///< the window's reach from a tool's surface, in node spacings along the wall
  double jacobi_damping = 0.5;  ///< weight of the line-Jacobi smoothing outside the window
  /// The window's factor in float (DenseCholesky): its solves, two per V-cycle, stream half the memory.
  bool single_precision_window = true;
};

class WallMultigrid final : public EquilibriumPreconditioner {
 public:
  /// A problem this preconditioner can serve: its nodes form a wall lattice, one energy point per node.
  static bool supports(const Problem& problem);
  /// Builds the coarse space and the symbolic parts (no level yet: build_level and install). The problem,
  /// `free` and `contacts` must outlive it. Throws std::invalid_argument when !supports(problem).
  WallMultigrid(const Problem& problem, const FreeDofs& free, const ContactActiveSet& contacts,
                const WallMultigridOptions& options);
  ~WallMultigrid() override;

  /// The refreshed parts at one configuration: the smoother's diagonal blocks and the coarse factor.
  class Level {
   public:
    Level();
    /// Per through-wall line (wall_lines): the inverse of H's block on the line's free nodes, 3L x 3L for L
    /// free nodes, stored column-major one after the other (line_offset).
    std::vector<double> line_inverse;
    Eigen::SparseMatrix<double> coarse_matrix;  ///< A_c, N/m
    SparseCholesky coarse;                      ///< its factor (float solves)
    Mat9Array tangents;                         ///< every node's tangent at the level's configuration
    double build_s = 0.0;                       ///< wall time of the build, s
  };
  /// Builds a level at x (m): every node's tangent, the diagonal blocks, the Galerkin coarse operator and its
  /// factor. Const and self-contained, so it may run on another thread while the installed level serves;
  /// `reuse` (a level no longer installed) keeps its factor's symbolic analysis. Throws NumericalError when
  /// the coarse operator is not positive definite.
  std::unique_ptr<Level> build_level(const Vec3Array& x, std::unique_ptr<Level> reuse = nullptr) const;
  /// Installs `level`; returns the one it replaces (for reuse).
  std::unique_ptr<Level> install(std::unique_ptr<Level> level);
  bool ready() const { return level_ != nullptr; }
  /// Rebuilds the exact window round the tools at x (after the frame's tools are placed in `contacts`).
  void prepare_window(const Vec3Array& x);
  /// The window again at a Newton step's own state when the tools on the wall's surface have other samples in
  /// contact there than when it was formed: a sample's penalty is about a hundred times the wall's stiffness,
  /// so a window without the samples a step added (or with those it dropped) leaves conjugate gradients that
  /// error to find (docs/model/24-implicit.md section 24.1). Otherwise the window stands.
  void follow_state(const Vec3Array& x) override;
  /// Nodes in the window now.
  std::size_t window_nodes() const { return window_.size(); }
  /// Wall time of the last build_level, s.
  double last_level_seconds() const;

  bool apply(const Vec3Array& r, Vec3Array& z) const override;
  /// An approximate P^{-1} (the parts added, without the operator; about 20 % stiffer than the Newton
  /// matrix's inverse on the vein's contacts): for the contact compliances of the haptic hand-off.
  bool solve_columns(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const override;
  nlohmann::json info() const override;
  long long version() const override { return version_; }
  void set_operator(const NewtonOperator* op) const override { op_ = op; }

  bool handles_contacts() const override { return true; }
  /// Tools that meet the wall's surface (embedded_contact.hpp) instead of its nodes: the window forms round
  /// them, and its block takes their penalty's Hessian at the contact's linearisation when the window is
  /// prepared.
  void set_embedded_contact(const EmbeddedContact* contact) { embedded_ = contact; }

 private:
  void smooth(const Vec3Array& b, Vec3Array& z, bool constrained) const;  // window solve + line Jacobi
  void coarse_correction(const Vec3Array& b, Vec3Array& z, bool constrained) const;  // z += P A_c^{-1} P^T b
  void update_coarse_contacts() const;  // the coarse level's contact constraints, G = N P
  void update_window_contacts() const;  // the Woodbury factors of the contacts

  const Problem& problem_;
  const FreeDofs& free_;
  const ContactActiveSet& contacts_;
  const EmbeddedContact* embedded_ = nullptr;
  WallMultigridOptions options_;
  // The tangents' positive form: the Newton operator's own where it has one (energy_tangents.hpp).
  TangentProjection projection_;
  std::vector<double> shift_;                                    // per node m_i / h^2, N/m
  std::vector<double> stab_diag_;                                // per node the stabiliser's diagonal, N/m
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> stab_rows_;  // the stabiliser's (scalar) Hessian, N/m
  // The wall's through-wall lines (a lattice column at one cross-section: its layers): their free nodes,
  // line by line (line_start), and where each line's inverse starts in Level::line_inverse.
  int layers_ = 1;
  std::vector<Index> line_start_, line_nodes_;
  std::vector<Index> line_slot_;  // per node its place in its line, -1 for a prescribed node
  std::vector<std::size_t> line_offset_;
  NodalProlongation prolongation_;
  std::unique_ptr<GalerkinHessian> galerkin_;
  std::unique_ptr<Level> level_;
  double window_m_ = 0.0;
  long long version_ = 0;
  int levels_built_ = 0;

  // The window: its nodes, each node's place in it (-1 outside), H's block there and its factor.
  std::vector<Index> window_;
  std::vector<Index> window_slot_;
  DenseCholesky window_factor_;
  std::vector<Index> window_samples_;  // the embedded contact's samples in contact when it was formed
  long long windows_followed_ = 0;     // windows formed again by follow_state
  Mat9Array window_tangents_;
  std::vector<Index> window_energies_;
  // The contacts inside the window and their Woodbury factors: Zc = A_W^{-1} N^T, (N Zc)^{-1}.
  mutable std::vector<Index> window_contacts_;
  mutable Vec3Array window_normals_;
  mutable Eigen::MatrixXd window_Z_;
  mutable Eigen::LDLT<Eigen::MatrixXd> window_NZ_;
  // The contacts seen by the coarse level: the coarse vectors whose prolongation keeps every contact's normal
  // displacement zero (G y = 0, row c of G = n_c^T P_c), by a Woodbury correction with Zg = A_c^{-1} G^T.
  mutable std::vector<Index> coarse_contacts_;
  mutable Vec3Array coarse_normals_;
  mutable long long coarse_contacts_version_ = -1;
  mutable Eigen::MatrixXd coarse_G_, coarse_Z_;
  mutable Eigen::LDLT<Eigen::MatrixXd> coarse_GZ_;
  mutable const NewtonOperator* op_ = nullptr;

  mutable Vec3Array b_, z1_, t_, y_;  // workspaces of apply()
  mutable Eigen::VectorXd wb_, cb_, cy_;
};

}  // namespace vascsim
