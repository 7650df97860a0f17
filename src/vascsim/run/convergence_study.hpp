#pragma once
// `vascsim converge`: the discretisation error of a scene at its own resolution, estimated from the scene run
// at coarser (and optionally one finer) node spacings and extrapolated with the observed order (Richardson,
// core/richardson.hpp; docs/convergence.md).
//
// The levels are one family only when the nodes fall alike under what loads the body: the same offset of the
// nearest node from each tool's axis and the same share of each region's asked extent selected (a tool's
// force moves by up to 8 % with where the nodes fall under it, a bonded patch's with its selected area). Each
// coarser or finer level takes the spacing, among a few within +-9 % of the nominal one, whose lattice
// matches the scene's; when none does, the study stops and says which tool or region differs instead of
// extrapolating. A tool's force counts only where its Hertz contact spans 1.4 node spacings at every level
// (run/contact_resolution.hpp).

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vascsim/core/richardson.hpp"
#include "vascsim/run/simulation.hpp"

namespace vascsim {

/// Where the nodes fall under what loads the body, compared between the levels of a study.
struct LatticeSignature {
  struct Entry {
    std::string
        what;  ///< "tool 'catheter' (nearest node off its axis, spacings)", "region 'indenter' (angle)"
    double value = 0.0;
    double tolerance = 0.0;  ///< two levels match when their values differ by at most this
  };
  std::vector<Entry> entries;
  int wall_layers = 0;  ///< node layers through the wall (0: not a layered wall)
  double spacing_m =
      0.0;  ///< the representative node spacing along the wall (run/../vessel_body along_wall_spacing_m)

  /// The first entry that differs from `other`'s by more than its tolerance, as "what: a here, b there";
  /// empty when they match.
  std::string mismatch(const LatticeSignature& other) const;
};

/// The signature of a built run.
LatticeSignature lattice_signature(Simulation& sim);

/// The scene with its node spacing (and a graded window's fine spacing) multiplied by `factor`, and no VTK or
/// surface output. Throws InputError when the scene has no geometry.node_spacing_m.
Scene scene_at_spacing(const Scene& scene, double factor);

struct ConvergenceOptions {
  std::filesystem::path out_dir;
  double ratio = 1.4142135623730951;  ///< spacing of one level over the next finer one, > 1
  int coarser_levels = 2;             ///< levels coarser than the scene's, >= 1 (2 with finer = false)
  bool finer = false;                 ///< also one level finer than the scene's (a second order estimate)
  double target = 0.0;                ///< a relative error to reach (0: none): the spacing that reaches it
  BuildChecks checks;                 ///< for every level's build (e.g. a node limit)
  /// Before each level's run: (level index in run order, levels, spacing factor, what it is).
  std::function<void(int, int, double, const std::string&)> on_level;
  /// After each output point of a level's run: (record, total steps).
  std::function<void(const StepRecord&, int)> on_step;
};

/// One resolution of the study.
struct ConvergenceLevel {
  double factor = 1.0;     ///< spacing / the scene's
  double spacing_m = 0.0;  ///< the representative spacing along the wall (h)
  int nodes = 0;
  double seconds = 0.0;
  bool user = false;  ///< the scene's own resolution
  std::filesystem::path out_dir;
  LatticeSignature signature;
  std::vector<double> tried_factors;  ///< factors whose lattice differed before this one matched
};

/// One output (a tool's or region's force or displacement, a probe) at one output point, over the levels.
struct ConvergenceOutput {
  std::string quantity;  ///< "catheter force_n", "tip displacement_m", ...
  std::string unit;      ///< "N" or "m"
  int step = 0;
  double load_factor = 0.0;
  double tool_displacement_m = -1.0;  ///< tools: their displacement at the step (m); -1 otherwise
  std::vector<double> values;         ///< per level, fine to coarse (the study's levels order)
  std::string status;                 ///< richardson_status_name, or "contact not resolved", "zero"
  Richardson estimate;                ///< from the three finest levels
  bool has_check = false;             ///< four levels: the three coarsest give a second order
  double check_order = 0.0;
  double user_error = 0.0;  ///< (f at the scene's spacing - f_ext) / f_ext
  double user_bound = 0.0;  ///< its GCI bound (|relative error| <= this with the factor of safety)
};

struct ConvergenceResult {
  std::vector<ConvergenceLevel> levels;  ///< fine to coarse
  int user_level = 0;                    ///< index of the scene's own resolution in `levels`
  std::vector<ConvergenceOutput> outputs;
  std::string refused;  ///< why no estimate was made (lattices that differ); empty otherwise
  nlohmann::json to_json() const;
};

/// Runs the study (each level's outputs in out_dir/level-<k>-<spacing>) and writes convergence.csv and
/// convergence.json to out_dir. Throws InputError for a scene it cannot vary (a haptic session, no node
/// spacing) and what the runs throw.
ConvergenceResult run_convergence_study(const Scene& scene, const ConvergenceOptions& options);

/// The spacing (m) at which `output`'s error would reach `target` (relative), from its order; 0 when it has
/// no estimate.
double spacing_for_target(const ConvergenceResult& result, const ConvergenceOutput& output, double target);

}  // namespace vascsim
