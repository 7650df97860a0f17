#include "vascsim/viewer/frame_presenter.hpp"

#include <limits>

namespace vascsim::viewer {

namespace {
constexpr std::size_t kForceHistory = 240;  // frames of force plotted in the HUD
}

FramePresenter::FramePresenter(render::GlContext& context, render::Renderer& renderer,
                               FrameExchange<ViewerFrame>& exchange)
    : context_(context), renderer_(renderer), exchange_(exchange) {}

bool FramePresenter::update(bool measure) {
  exchange_.update();
  const ViewerFrame& f = exchange_.front();
  upload_ms_ = 0.0;
  if (f.render.sequence == 0 || f.render.sequence == uploaded_) return false;
  renderer_.upload(f.render, measure);
  upload_ms_ = renderer_.timing().upload_ms;
  uploaded_ = f.render.sequence;
  log_.simulation_frame(f.timing);
  force_history_.push_back(static_cast<float>(f.tool_force_n));
  if (force_history_.size() > kForceHistory) force_history_.pop_front();
  return true;
}

void FramePresenter::draw(const render::OrbitCamera& camera, const render::RenderSettings& settings) {
  const auto [w, h] = context_.framebuffer_size();
  renderer_.draw(camera, settings, context_.draw_framebuffer(), w, h);
}

render::HudStats FramePresenter::hud_stats(double visual_fps) const {
  const ViewerFrame& f = exchange_.front();
  const LiveFrameInfo& i = f.info;
  render::HudStats s;
  s.scene_name = f.scene_name;
  s.model_name = f.model;
  s.device = i.has_tool ? i.device : std::string();
  s.visual_fps = visual_fps;
  s.deformation_steps_per_s = i.steps_per_s;
  s.haptic_rate_hz = i.haptics.achieved_rate_hz;
  s.haptic_p99_jitter_us = 1e3 * i.haptics.jitter_p99_ms;
  s.tool_force_n = f.tool_force_n;
  if (i.has_tool && i.haptics.ticks > 0) {
    // What the hand gets, beside the model's force (the final line of a realtime run says the same).
    s.device_force_n = i.haptics.last_force_sent_n;
    s.tool_lag_m = i.sample.tool_lag_m;
    s.force_age_ms = i.haptics.force_latency_mean_ms;
  }
  s.force_threshold_n = f.force_threshold_n;
  s.force_history_n.assign(force_history_.begin(), force_history_.end());
  s.nodes = f.nodes;
  s.triangles = f.render.triangles.size();
  // A model that reports no residual leaves it 0 (StepReport): shown as not reported.
  s.solver_residual = i.sample.residual > 0.0 ? i.sample.residual : std::numeric_limits<double>::quiet_NaN();
  s.sim_time_s = i.sample.sim_time_s;
  s.simulation_ms = f.timing.simulation_ms;
  s.map_ms = f.timing.map_ms;
  s.normals_ms = f.timing.normals_ms;
  s.upload_ms = upload_ms_;
  s.draw_ms = renderer_.timing().draw_ms;
  s.paused = i.paused;
  s.recording = i.recording;
  s.message = i.message;
  s.gl_renderer = context_.description();
  return s;
}

}  // namespace vascsim::viewer
