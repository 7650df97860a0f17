#pragma once
// Rest-state discretisation of the point-primitive model (docs/model/ sections 3-5): per-node support radii,
// neighbour lists, the precomputed gradient vectors d_ij in CSR form with a transposed copy for
// gather-form assembly, nodal volumes and masses. Immutable during a run (total Lagrangian).

#include <array>
#include <string>
#include <vector>

#include "vascsim/geometry/node_cloud.hpp"
#include "vascsim/model/local_fit.hpp"
#include "vascsim/model/material.hpp"

namespace vascsim {

enum class VolumeRule {
  TetPartition,   ///< V_i = 1/4 sum_{T containing i} |T| (sound default, docs/model/00-design-decisions.md,
                  ///< decision 3)
  MuellerKernel,  ///< Mueller 2004 kernel density estimate V_i = m_i / rho_i (paper-literal option)
  /// The tet partition times volume_factors: Simpson weights across a lattice's layers, so that the nodal sum
  /// integrates a bending field's energy exactly (geometry/lattice_quadrature.hpp; the quadratic basis's
  /// partner)
  Simpson
};

struct DiscretizationOptions {
  double support_radius_factor =
      2.0;  ///< h = factor * mean nearest spacing (docs/model/00-design-decisions.md, decision 7)
  int min_neighbours = 12;        ///< K_min
  double min_eigen_ratio = 1e-3;  ///< lambda_min / lambda_max of A_i / tr(A_i) (cond <= 1e3)
  double growth_factor = 1.2;     ///< h_i <- 1.2 h_i when a node fails the guard
  int max_growths = 3;            ///< then fail loudly
  /// Named before the growths when the guard fails: the fix a caller knows of (a scene whose lattice is
  /// coarse for its wall: "reduce geometry.node_spacing_m (...)"); empty: none.
  std::string coarse_spacing_advice;
  VolumeRule volume = VolumeRule::TetPartition;
  GradientBasis basis = GradientBasis::Linear;  ///< the local fit's polynomial (local_fit.hpp)
  /// Supports that follow a wall (docs/model/03-neighbourhoods.md section 3.1): per node the wall's unit
  /// normal, and the ratio of the lattice spacing along the wall to the spacing of its node layers (>= 1). A
  /// node's support is then an ellipsoid: radius h_i along the normal and wall_stretch h_i in the wall's
  /// tangent plane, with the weights w_ij = W(|M_i X_ij|, h_i), M_i = n n^T + (I - n n^T) / wall_stretch.
  /// Empty normals: isotropic supports.
  std::vector<Vec3> wall_normals;
  double wall_stretch = 1.0;
  /// Optional, per node (a graded lattice, geometry.refine): its own stretch instead of wall_stretch.
  std::vector<double> wall_stretches;
  /// Optional with wall_stretches, per node: a unit direction in the wall's plane (a swept vessel's
  /// centre-line tangent) and the stretch along it; wall_stretches is then the stretch across it (around the
  /// vessel). A graded lattice's cells can be four times longer one way than the other, and one stretch from
  /// their mean side reaches only one step along the long side, where a quadratic fit needs two
  /// (docs/model/21-vessel-geometry.md section 21.1).
  std::vector<Vec3> wall_axes;
  std::vector<double> wall_axial_stretches;
  /// Optional, per node: its depth in the wall, m. Given, the through-wall part of X_ij is the depth
  /// difference, so the ellipsoid follows a curved wall's layers instead of the node's tangent plane.
  std::vector<double> wall_depths;
  /// VolumeRule::Simpson: per node, the factor on its tet-partition volume (simpson_volume_factors, filled by
  /// the simulation from the body's lattice).
  std::vector<double> volume_factors;
  /// The scene's choice (discretization.support): Wall asks the simulation to fill wall_normals and
  /// wall_stretch from the body's wall coordinates.
  enum class Support { Isotropic, Wall } support = Support::Isotropic;
  /// How far a wall support reaches through the wall (docs/model/03-neighbourhoods.md section 3.2): Layers,
  /// radius h_i as the support's own rule gives it; Thickness, the through-wall distance scaled so that the
  /// wall's far surface lies at kThicknessReach h_0 from the near one (never shortened below h_i), so that
  /// every node's fit sees every layer.
  enum class WallReach { Layers, Thickness } wall_reach = WallReach::Layers;
  /// The wall's thickness (outer to inner layer), m: WallReach::Thickness and WallQuadrature::Gauss need it.
  double wall_thickness_m = 0.0;
  /// Where a node's strain energy is evaluated (docs/model/04-volumes.md section 4.4): Nodes, at the node
  /// (V_i psi(F_i)); Gauss, at two Gauss points across the node's slab of the wall (the depths within half a
  /// layer step of its own, clipped to the wall), each with the gradient the node's fit gives there, F_i +
  /// s_q dF_i/dn: a bending field's energy is then integrated exactly whatever the nodal volumes; GaussCell,
  /// at 2 x 2 x 2 Gauss points over the node's whole cell of the wall (its slab across, its column and
  /// cross-section steps along, wall_cells), F_i + sum_k o_qk dF_i/du_k: the strain's variation along the
  /// wall is integrated too, not only across it. Both need a wall support with depths and a curvature-fitting
  /// basis.
  enum class WallQuadrature { Nodes, Gauss, GaussCell } wall_quadrature = WallQuadrature::Nodes;
  /// The quadratic basis on a wall (wall_normals given): also fit the cube of the through-wall coordinate,
  /// (X_ij . n_i)^3, so that a node's gradient and its points' gradients are exact for a displacement cubic
  /// across the wall, as transverse shear makes it (docs/model/05-local-fit.md section 5.3). Nodes whose
  /// neighbourhood cannot tell the cube from the quadratic monomials (a wall of three layers) keep the
  /// quadratic fit.
  bool wall_cube = false;
  /// Which cubic monomials the wall fit adds to the quadratic basis with wall_cube
  /// (docs/model/05-local-fit.md section 5.4), in the node's wall frame (z through the wall, s1 s2 along the
  /// cell's edges): Cube, z^3 alone; ThroughWall, the six cubics with a through-wall factor (z^3, z^2 s, z s
  /// s'), which a plate's bending under a varying moment and its transverse shear are made of. ThroughWall
  /// needs WallQuadrature::GaussCell (the cubics' gradients at the points vary with the products of their
  /// offsets).
  enum class WallCubics { Cube, ThroughWall } wall_cubics = WallCubics::Cube;
  /// WallQuadrature::GaussCell: per node, its cell along the wall (filled by the simulation from the body's
  /// lattice).
  struct WallCell {
    std::array<Vec3, 2> edges;  ///< the cell's two edges along the wall (column and cross-section steps), m
    std::array<double, 2> centre{
        0, 0};  ///< the cell's centre from the node along each edge, m (0 but at an end)
  };
  std::vector<WallCell> wall_cells;
  /// The spacing of the wall's node layers, m: WallQuadrature::Gauss needs it.
  double wall_layer_spacing_m = 0.0;
  /// The quadratic fit's guard, on top of the linear one: at least this many neighbours (9 unknowns per
  /// component; twice that for a least-squares fit that averages), and lambda_min / lambda_max of B_i /
  /// tr(B_i) at least quadratic_min_eigen_ratio (docs/model/05-local-fit.md section 5.1 for how these were
  /// chosen).
  int quadratic_min_neighbours = 18;
  double quadratic_min_eigen_ratio = 1e-6;
};

struct NeighbourhoodTrial;  // one node's neighbourhood at a trial support radius (discretization.cpp)

/// One compressed-sparse-row table of pair data: row r lists (col, d, w).
struct PairTable {
  std::vector<Index> row_start;  ///< #rows + 1
  std::vector<Index> col;        ///< the other node
  Vec3Array d;                   ///< gradient vector, 1/m
  std::vector<double> w;         ///< kernel weight, 1/m^3
  /// With Gauss points (else empty): the derivatives of d along the row node's point directions
  /// (Discretization::point_directions, G per pair, pair-major: e[G p + k]), 1/m^2.
  Vec3Array e;
  Index row_size(Index r) const { return row_start[r + 1] - row_start[r]; }
};

class Discretization {
 public:
  Discretization(const NodeCloud& cloud, const Material& material, const DiscretizationOptions& options = {});

  Index num_nodes() const { return static_cast<Index>(X_.size()); }
  const Vec3Array& rest_positions() const { return X_; }
  const std::vector<Tet>& tets() const { return tets_; }

  /// Row i: j in N_i with d_ij = w_ij A_i^{-1} (X_j - X_i) and w_ij (Eq. 4 with the E1 sign fix).
  const PairTable& pairs() const { return pairs_; }
  /// Row k: the nodes i with k in N_i, each with d_ik and w_ik (for the gather-form force).
  const PairTable& transposed() const { return transposed_; }
  /// d_ii = -sum_j d_ij, 1/m.
  const Vec3Array& self_d() const { return self_d_; }
  /// tr(A_i), 1/m (used by the stabiliser's c_i).
  const std::vector<double>& moment_trace() const { return moment_trace_; }
  /// A_i = sum_j w_ij X_ij X_ij^T, 1/m (the moment matrix of Eq. 4; d_ij = w_ij A_i^{-1} X_ij with the linear
  /// basis).
  const std::vector<Mat3>& moment_matrices() const { return moment_; }
  GradientBasis basis() const { return basis_; }
  /// The residuals of node i's fit over its neighbours as a linear map of its stencil (i, N_i in the order of
  /// row i of pairs()): r_ij = (y_j - y_i) - fit_i(X_ij) = sum_a R(j, a) y_a, a K x (K + 1) matrix (K =
  /// |N_i|), column 0 for node i. Zero on every field the basis reproduces (affine or quadratic). quadratic:
  /// the residuals of a quadratic fit over the same neighbourhood and weights instead, whatever the basis (a
  /// least-squares projection; monomials the neighbourhood cannot tell apart are dropped).
  Eigen::MatrixXd fit_residual_operator(Index i, bool quadratic = false) const;

  const std::vector<double>& volumes() const { return V_; }         ///< V_i, m^3
  const std::vector<double>& masses() const { return m_; }          ///< m_i = rho V_i, kg
  const std::vector<double>& support_radius() const { return h_; }  ///< h_i, m

  double mean_spacing() const { return mean_spacing_; }  ///< Delta-bar, m
  double min_spacing() const { return min_spacing_; }    ///< smallest nearest-neighbour distance, m
  double total_volume() const;                           ///< sum V_i, m^3
  double tet_volume() const { return tet_volume_; }      ///< sum |T|, m^3
  double mean_neighbours() const;
  int grown_nodes() const { return grown_nodes_; }  ///< nodes whose h_i had to grow
  /// DiscretizationOptions::wall_cube: the nodes whose fit holds the through-wall cube (0 without it).
  int wall_cube_nodes() const { return cube_nodes_; }
  /// Supports that follow the wall: their reach along the wall over their reach through it
  /// (docs/model/03-neighbourhoods.md section 3.1); 0 with isotropic supports.
  double wall_stretch() const { return wall_stretch_; }
  /// The factor on the through-wall distance of a wall support (1 with WallReach::Layers;
  /// docs/model/03-neighbourhoods.md section 3.2).
  double wall_across_scale() const { return wall_across_scale_; }
  const Material& material() const { return material_; }
  const NodeCloud& cloud() const { return cloud_; }

  /// G_i = sum_j (u_j - u_i) d_ij^T (Eq. 2-3, docs/model/06-gradients.md). With eq3_literal_sign the paper's
  /// printed x_ij = x_i - x_j is used, which returns -G (negative test E1 only).
  Mat3 displacement_gradient(Index i, const Vec3Array& u, bool eq3_literal_sign = false) const;
  /// F_i = sum_j (x_j - x_i) d_ij^T.
  Mat3 deformation_gradient(Index i, const Vec3Array& x) const;

  /// The points at which each node's strain energy is evaluated (DiscretizationOptions::WallQuadrature): 1
  /// (the node), 2 (Gauss points across its slab of the wall) or 8 (2 x 2 x 2 over its cell), each weighing
  /// V_i / points.
  int energy_points() const { return energy_points_; }
  /// The directions u_k a point's offset is measured along: 0 (one point per node), 1 (the wall normal) or 3
  /// (the normal and the cell's two edges along the wall); with the through-wall cube one more, the last,
  /// whose "offset" is the square of the offset along the normal (m^2): the cube's gradient grows with it;
  /// with DiscretizationOptions::WallCubics::ThroughWall six more, the products of two of the three offsets.
  int point_directions() const { return point_directions_; }
  static constexpr int kMaxPointDirections = 9;
  /// Point q of node i: its offset from the node along direction k, m (m^2 for the cube's direction).
  double point_offset(Index i, int q, int k = 0) const {
    return energy_points_ == 1
               ? 0.0
               : point_offset_[(static_cast<std::size_t>(i) * static_cast<std::size_t>(energy_points_) +
                                static_cast<std::size_t>(q)) *
                                   static_cast<std::size_t>(point_directions_) +
                               static_cast<std::size_t>(k)];
  }
  /// With Gauss points: e_ii,k = -sum_j e_ij,k, 1/m^2 (1/m^3 for the cube's direction; G per node; empty
  /// otherwise).
  const Vec3Array& self_e() const { return self_e_; }
  /// dF_i/du_k = sum_j (x_j - x_i) e_ij,k^T, 1/m, for k < point_directions(), written to D[k].
  void deformation_gradient_derivatives(Index i, const Vec3Array& x, Mat3* D) const;
  /// The deformation gradient at point q of node i from F_i and its derivatives D
  /// (deformation_gradient_derivatives): F_i + sum_k point_offset(i, q, k) D[k].
  Mat3 point_gradient(Index i, int q, const Mat3& F, const Mat3* D) const {
    Mat3 Fq = F;
    for (int k = 0; k < point_directions_; ++k) Fq += point_offset(i, q, k) * D[k];
    return Fq;
  }

 private:
  void build_neighbourhoods(const DiscretizationOptions& opt);
  void store_gradient_vectors(const std::vector<NeighbourhoodTrial>& trials,
                              const DiscretizationOptions& opt);
  std::string growth_advice(const std::vector<int>& failed, double h0,
                            const DiscretizationOptions& opt) const;
  void compute_volumes(const DiscretizationOptions& opt);
  void place_wall_points(const DiscretizationOptions& opt);
  /// Fits the through-wall cube at node i (DiscretizationOptions::wall_cube); false where it is not
  /// resolvable.
  bool add_wall_cube(Index i, const Vec3& normal, const std::vector<Index>& nbr,
                     const DiscretizationOptions& opt);
  /// Fits the cubics of DiscretizationOptions::WallCubics::ThroughWall at node i; false where they are not
  /// resolvable (the caller then tries the cube alone).
  bool add_wall_cubics(Index i, const std::vector<Index>& nbr, const DiscretizationOptions& opt);
  Eigen::MatrixXd quadratic_residual_operator(Index i) const;
  /// The wall normal the wall-quadratic basis fits node i in (nullptr for the other bases).
  const Vec3* fit_normal(Index i) const {
    return fit_normals_.empty() ? nullptr : &fit_normals_[static_cast<std::size_t>(i)];
  }
  /// The wall-quadratic basis's normal, or the wall's normal from the options for the other bases.
  const Vec3* fit_normal_or(Index i, const DiscretizationOptions& opt) const {
    const Vec3* n = fit_normal(i);
    return n ? n : &opt.wall_normals[static_cast<std::size_t>(i)];
  }

  NodeCloud cloud_;
  Material material_;
  Vec3Array X_;
  std::vector<Tet> tets_;
  PairTable pairs_, transposed_;
  Vec3Array self_d_;
  std::vector<double> moment_trace_, V_, m_, h_;
  std::vector<Mat3> moment_;
  GradientBasis basis_ = GradientBasis::Linear;
  std::vector<Vec9> fit_;  // quadratic bases: w_ij B_i^{-1} p(X_ij / h_i) per pair (dimensionless)
  Vec3Array fit_normals_;  // wall-quadratic basis: the wall's unit normal per node
  double mean_spacing_ = 0.0, min_spacing_ = 0.0, tet_volume_ = 0.0;
  int grown_nodes_ = 0;
  int cube_nodes_ = 0;
  double wall_stretch_ = 0.0;
  double wall_across_scale_ = 1.0;
  int energy_points_ = 1;
  int point_directions_ = 0;
  int linear_directions_ = 0;         // the point directions whose offset is a length (the first ones)
  std::vector<double> point_offset_;  // energy_points x point_directions per node with Gauss points, m
  Vec3Array point_axes_;              // the point directions u_k per node (unit), point_directions per node
  Vec3Array self_e_;
};

}  // namespace vascsim
