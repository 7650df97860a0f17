#include "vascsim/viewer/timing_log.hpp"

#include <fmt/format.h>

#include "vascsim/core/statistics.hpp"

namespace vascsim::viewer {

void TimingLog::visual_frame(double frame_ms, double upload_ms, double draw_ms, double hud_ms) {
  frame_ms_.push_back(frame_ms);
  upload_ms_.push_back(upload_ms);
  draw_ms_.push_back(draw_ms);
  hud_ms_.push_back(hud_ms);
}

void TimingLog::simulation_frame(const PrepareTiming& t) {
  simulation_ms_.push_back(t.simulation_ms);
  map_ms_.push_back(t.map_ms);
  normals_ms_.push_back(t.normals_ms);
  fill_ms_.push_back(t.fill_ms);
}

void TimingLog::restart(double wall_s) {
  start_s_ = wall_s;
  for (auto* v :
       {&frame_ms_, &upload_ms_, &draw_ms_, &hud_ms_, &simulation_ms_, &map_ms_, &normals_ms_, &fill_ms_})
    v->clear();
}

std::string TimingLog::summary(double wall_s, double steps_per_s) const {
  const double elapsed = wall_s - start_s_;
  const double fps = elapsed > 0.0 ? static_cast<double>(frame_ms_.size()) / elapsed : 0.0;
  return fmt::format(
      "{} visual frames in {:.2f} s: {:.1f} fps (render thread median {:.1f} ms: upload {:.2f}, draw {:.2f}, "
      "hud "
      "{:.2f}); {} simulation frames shown, {:.1f} steps/s (median: simulation {:.2f} ms, MLS map {:.2f} ms, "
      "normals {:.2f} ms, rest {:.2f} ms)",
      frame_ms_.size(), elapsed, fps, median(frame_ms_), median(upload_ms_), median(draw_ms_),
      median(hud_ms_), simulation_ms_.size(), steps_per_s, median(simulation_ms_), median(map_ms_),
      median(normals_ms_), median(fill_ms_));
}

}  // namespace vascsim::viewer
