#pragma once
// Small helpers that several test files share: the source tree's files, the haptic block scene, running a
// simulation to its end, the volume of a node cloud's virtual tetrahedra, and wall-clock seconds. The test
// files are compiled as unity batches (tests/CMakeLists.txt), so a helper two files need lives here, not in
// each file's anonymous namespace.

#include <algorithm>
#include <chrono>
#include <limits>
#include <string>
#include <vector>

#include "vascsim/geometry/node_cloud.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim::test {

/// A file of the source tree by its path relative to the repository's root.
inline std::string source_path(const std::string& relative) {
  return std::string(VASCSIM_SOURCE_DIR) + "/" + relative;
}

/// tests/data/haptic-block.json (the haptic and live sessions' block) with `sets` applied like --set.
inline Scene haptic_block_scene(const std::vector<std::string>& sets = {}) {
  return load_scene(source_path("tests/data/haptic-block.json"), sets);
}

/// The --set that puts the haptic block on a 1 mm lattice (196 nodes instead of 1,183): for tests of a
/// session's bookkeeping (ticks, frames, replays, the sign of the force), which do not depend on the
/// resolution.
inline const std::vector<std::string> kCoarseHapticBlock = {"geometry.node_spacing_m=1e-3"};

/// Advances every step of the run; the last step's record.
inline StepRecord run_to_end(Simulation& sim) {
  StepRecord rec;
  for (int k = 1; k <= sim.model().num_steps(); ++k) rec = sim.advance(k);
  return rec;
}

/// The summed signed volume of the cloud's tetrahedra (m^3); the smallest one's in *min_volume when given.
inline double total_tet_volume(const NodeCloud& c, double* min_volume = nullptr) {
  double v = 0.0, vmin = std::numeric_limits<double>::infinity();
  for (const Tet& t : c.tets) {
    const double vt =
        signed_volume(c.positions[t[0]], c.positions[t[1]], c.positions[t[2]], c.positions[t[3]]);
    v += vt;
    vmin = std::min(vmin, vt);
  }
  if (min_volume) *min_volume = vmin;
  return v;
}

/// Wall-clock seconds since t0.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace vascsim::test
