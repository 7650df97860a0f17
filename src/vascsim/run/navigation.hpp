#pragma once
// A flexible instrument advanced through a vessel (docs/model/26-rod.md section 26.7): the scene's
// "instrument" fed and turned at its access port by the scene's drive, frame by frame, inside the vessel's
// lumen. The lumen is rigid here (the inside of the wall round the centre-line, of radius outer radius less
// wall thickness); the deformable wall's coupling is not built. Each frame is a quasi-static equilibrium
// with Coulomb friction lagged over the frame (rod/lumen_friction.hpp).

#include <filesystem>
#include <functional>
#include <vector>

#include "vascsim/scene/scene.hpp"

namespace vascsim {

/// One frame of a navigation, SI units.
struct NavigationFrame {
  double time_s = 0.0;
  double inserted_m = 0.0;    ///< rod past the access port
  double twist_rad = 0.0;     ///< the proximal end's turn about the port's axis
  Vec3 tip_m = Vec3::Zero();  ///< the distal end
  double tip_s_m = 0.0;  ///< the tip's nearest centre-line point, arc length from the centre-line's start
  double insertion_force_n =
      0;                    ///< the hand's force along the port's axis holding the insertion (> 0: pushing)
  double torque_n_m = 0.0;  ///< the hand's moment about the port's axis holding the turn
  double wall_force_max_n = 0;           ///< the largest contact force on one node of the rod
  double wall_force_total_n = 0;         ///< the sum of the contact forces' magnitudes
  Vec3 wall_force_sum_n = Vec3::Zero();  ///< the contact forces on the rod added as vectors
  double outside_max_m =
      0.0;  ///< how far the rod's surface goes beyond the lumen's wall at most (<= 0: never)
  int nodes_in_contact = 0;
  int newton_iterations = 0;
  bool converged = false;
  bool perforation_risk = false;  ///< wall_force_max_n above the instrument's perforation_force_n
  double wall_ms = 0.0;           ///< the frame's solve, wall-clock ms
};

struct NavigationResult {
  std::vector<NavigationFrame> frames;  ///< the frame at time 0 (the placement) first
  Vec3Array final_positions_m;          ///< the rod's nodes after the last frame
  double lumen_radius_m = 0.0;
  int unconverged = 0;
  int perforation_frames = 0;
};

struct NavigationOptions {
  std::filesystem::path
      out_dir;  ///< instrument.csv and instrument_final.csv go here (empty: nothing written)
  /// Called after every frame (done and total frames).
  std::function<void(int done, int total)> on_progress;
};

/// Runs the scene's instrument. Throws InputError when the scene has no instrument, its geometry is not a
/// vessel with a centre-line, or the instrument does not fit the lumen.
NavigationResult run_navigation(const Scene& scene, const NavigationOptions& options);

}  // namespace vascsim
