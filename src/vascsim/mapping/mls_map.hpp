#pragma once
// Moving-least-squares map from the interior nodes to a surface mesh (paper Eqs. 25-39,
// docs/model/20-mls-map.md): shape functions phi_vi with a linear basis shifted to the surface point and
// scaled by the support radius, precomputed once at rest in double into a CSR matrix Phi (#V by #N); per
// frame one sparse mat-vec x_s = S_v + Phi (x - X), and the transpose f_i = sum_v phi_vi f_v for contact and
// haptic forces. Rest positions only: the map is never rebuilt during a run (total Lagrangian).

#include <array>
#include <string>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

struct MlsMapOptions {
  /// r0 = factor * mean nearest-neighbour node spacing; docs/model/20-mls-map.md section 20.2 allows 2.0-2.5.
  /// Measured (vein tube boundary vertices plus points up to Delta/2 off the wall; jittered box faces and
  /// corners): 2.25 needs no growth anywhere, max cond(A^) 116 (8x below the limit), mean |S| 25 (the 15-30
  /// budget of docs/model/20-mls-map.md); 2.0 grows box corners and reaches cond 279 off the wall; 2.5 costs
  /// 50 % more nonzeros per frame.
  double support_radius_factor = 2.25;
  int min_nodes = 8;            ///< |S(X)| >= 8 (docs/model/20-mls-map.md section 20.2, T11)
  double cond_limit = 1e3;      ///< lambda_max / lambda_min of the scaled moment matrix A^ (4.3)
  double growth_factor = 1.25;  ///< r <- 1.25 r for a vertex that fails a guard (4.3)
  /// Then throw NumericalError (T15). 6 (up to 3.8 r0): on a layered wall the nearest spacing is the layers'
  /// and the columns can be 4x farther apart (four layers through the vein's 0.3 mm wall at 0.4 mm: 4 growths
  /// needed). Each vertex keeps the smallest radius that passes the guard, so a vertex that passed at fewer
  /// is unchanged.
  int max_growths = 6;
  /// Named before the growths when the guard fails: the fix a caller knows of (a scene whose lattice is
  /// coarse for its wall: "reduce geometry.node_spacing_m (...)"); empty: none.
  std::string coarse_spacing_advice;
};

/// Summary of the precomputation, for logging.
struct MlsMapReport {
  double mean_support = 0.0;  ///< mean |S(X)| over the surface vertices
  Index min_support = 0;
  Index max_support = 0;
  double max_cond = 0.0;       ///< largest cond(A^) accepted
  Index grown_vertices = 0;    ///< vertices whose radius had to grow
  double base_radius_m = 0.0;  ///< r0
  double max_radius_m = 0.0;   ///< largest radius used
};

class MlsMap {
 public:
  /// Builds Phi from the rest node positions X_i (#N, m) and rest surface vertex positions S_v (#V, m).
  /// Throws InputError for invalid options or non-finite / coincident input, NumericalError naming the
  /// first vertex whose support stays too small or rank-deficient after max_growths growths.
  MlsMap(const Vec3Array& rest_nodes_m, const Vec3Array& rest_surface_m, const MlsMapOptions& options = {});

  Index num_nodes() const { return static_cast<Index>(rest_nodes_.size()); }
  Index num_vertices() const { return static_cast<Index>(rest_surface_.size()); }

  /// x_s = S_v + sum_i phi_vi (x_i - X_i) (docs/model/20-mls-map.md, displacement form). x_nodes_m: #N, m.
  void map_positions(const Vec3Array& x_nodes_m, Vec3Array& x_surface_m) const;
  /// u_s = Phi u (no rest offset): the linear part of the map. u_nodes_m: #N, m.
  void map_displacements(const Vec3Array& u_nodes_m, Vec3Array& u_surface_m) const;
  /// float32 run-time variant for render buffers: x_s = S_v + Phi_f32 u with float shape functions and
  /// float in/out, accumulated in double (the mat-vec is bandwidth-bound, so the wider sum costs nothing
  /// and keeps the 1e-5 Delta bound of T11 for displacements of many Delta).
  void map_displacements_f32(const std::vector<Eigen::Vector3f>& u_nodes_m,
                             std::vector<Eigen::Vector3f>& x_surface_m) const;
  /// f_i = sum_v phi_vi f_v (Phi^T f) in gather form over a stored transpose; no atomics, deterministic.
  /// f_surface_n: #V, N. Preserves total force (partition of unity) and virtual work.
  void map_forces_to_nodes(const Vec3Array& f_surface_n, Vec3Array& f_nodes_n) const;

  /// CSR of Phi: row v holds the nodes of S(S_v) in increasing order.
  const std::vector<Index>& row_start() const { return row_start_; }
  const std::vector<Index>& columns() const { return col_; }
  const std::vector<double>& values() const { return val_; }
  const Vec3Array& rest_surface() const { return rest_surface_; }
  const std::vector<double>& vertex_radius() const { return radius_; }  ///< final r per vertex, m
  const std::vector<double>& vertex_cond() const { return cond_; }      ///< cond(A^) per vertex
  const MlsMapReport& report() const { return report_; }

 private:
  void build_transpose();
  void fill_report(double r0, const std::vector<int>& growths);
  void check_node_count(std::size_t given, const char* what) const;
  template <class Term, class Store>
  void for_each_row(Term&& term, Store&& store) const;

  Vec3Array rest_nodes_;
  Vec3Array rest_surface_;
  std::vector<Index> row_start_, col_;
  std::vector<double> val_;
  std::vector<float> val_f32_;
  std::vector<Index> t_row_start_, t_col_;  // Phi^T: row i lists the vertices v with i in S(S_v)
  std::vector<double> t_val_;
  std::vector<double> radius_, cond_;
  MlsMapReport report_;
};

}  // namespace vascsim
