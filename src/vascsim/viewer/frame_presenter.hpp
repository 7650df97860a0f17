#pragma once
// The render thread's side of the frame hand-off: it takes the newest frame the simulation thread published
// (never waiting for one), uploads it when it is new, draws it, and gives the HUD its numbers (with the force
// history it keeps).

#include <deque>

#include "vascsim/core/frame_exchange.hpp"
#include "vascsim/render/camera.hpp"
#include "vascsim/render/gl_context.hpp"
#include "vascsim/render/hud.hpp"
#include "vascsim/render/renderer.hpp"
#include "vascsim/viewer/timing_log.hpp"
#include "vascsim/viewer/viewer_frame.hpp"

namespace vascsim::viewer {

class FramePresenter {
 public:
  FramePresenter(render::GlContext& context, render::Renderer& renderer,
                 FrameExchange<ViewerFrame>& exchange);

  /// Takes the newest frame and uploads it if it is new (true then). `measure`: glFinish around the upload.
  bool update(bool measure);
  /// A frame has been uploaded.
  bool has_frame() const { return uploaded_ != 0; }
  const ViewerFrame& frame() const { return exchange_.front(); }
  /// Draws the last uploaded frame into the context's framebuffer.
  void draw(const render::OrbitCamera& camera, const render::RenderSettings& settings);
  /// The HUD's numbers for this frame.
  render::HudStats hud_stats(double visual_fps) const;
  TimingLog& log() { return log_; }
  double upload_ms() const { return upload_ms_; }

 private:
  render::GlContext& context_;
  render::Renderer& renderer_;
  FrameExchange<ViewerFrame>& exchange_;
  std::uint64_t uploaded_ = 0;
  double upload_ms_ = 0.0;
  std::deque<float> force_history_;
  TimingLog log_;
};

}  // namespace vascsim::viewer
