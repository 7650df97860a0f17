#pragma once
// The viewer's frame times, for `vascsim view --measure` and docs/performance.md: per visual frame the
// renderer's upload and draw (and the HUD), per new simulation frame the simulation side's split (the model's
// frame, the MLS map, the normals), and the wall clock, so frames per second and steps per second come out of
// the same run. Medians: robust to the other processes on a shared machine.

#include <string>
#include <vector>

#include "vascsim/viewer/viewer_frame.hpp"

namespace vascsim::viewer {

class TimingLog {
 public:
  /// A visual frame that took `frame_ms` in all (its render-thread share), with the renderer's split.
  void visual_frame(double frame_ms, double upload_ms, double draw_ms, double hud_ms);
  /// A new simulation frame reached the render thread.
  void simulation_frame(const PrepareTiming& timing);
  /// Frames counted from here on (the first frames compile shaders and fill caches).
  void restart(double wall_s);

  /// One line: visual fps (visual frames / wall time since restart) and the medians.
  std::string summary(double wall_s, double steps_per_s) const;
  std::size_t visual_frames() const { return frame_ms_.size(); }

 private:
  double start_s_ = 0.0;
  std::vector<double> frame_ms_, upload_ms_, draw_ms_, hud_ms_;
  std::vector<double> simulation_ms_, map_ms_, normals_ms_, fill_ms_;
};

}  // namespace vascsim::viewer
