#pragma once
// The viewer's side of a live session (run/live_session.hpp): on the simulation thread, after every frame, it
// fills the back slot of the frame exchange with the picture (the MLS-mapped surface, the tools, the force
// arrow, the overlays the UI asked for) and the HUD's numbers, and publishes it to the render thread. After a
// (re)build it places the mouse device's workspace at the scene's tool (mouse_workspace.hpp).
//
// Realtime, it skips preparing a frame while the render thread has not taken the previous one (the frame
// would replace it unseen): the MLS map is then not paid for pictures nobody sees. The UI's overlay choices
// reach it through relaxed atomics.

#include <atomic>
#include <optional>

#include "vascsim/core/frame_exchange.hpp"
#include "vascsim/interaction/mouse_keyboard_device.hpp"
#include "vascsim/viewer/surface_snapshot.hpp"
#include "vascsim/viewer/tool_drawing.hpp"
#include "vascsim/viewer/viewer_frame.hpp"

namespace vascsim::viewer {

/// What the UI thread asks the simulation thread to put into the frames (any thread writes, relaxed).
struct OverlayRequests {
  std::atomic<bool> nodes{false}, tets{false};
  std::atomic<bool> stress{false};  ///< the colour field is the von Mises stress (else the displacement)
  /// The safety threshold, N (0: the scene's, force_threshold_n()).
  std::atomic<double> force_threshold_n{0.0};
};

class FrameBuilder final : public LiveObserver {
 public:
  /// `skip_unseen`: do not prepare a frame while the previous one is still pending (realtime).
  FrameBuilder(FrameExchange<ViewerFrame>& exchange, MouseKeyboardDevice& mouse,
               const OverlayRequests& overlays, bool skip_unseen);

  void built(Simulation& simulation, std::optional<std::size_t> tool) override;
  void frame(Simulation& simulation, const LiveFrameInfo& info) override;

 private:
  FrameExchange<ViewerFrame>& exchange_;
  MouseKeyboardDevice& mouse_;
  const OverlayRequests& overlays_;
  bool skip_unseen_;
  SurfaceSnapshot surface_;
  std::optional<std::size_t> tool_;
  std::uint64_t builds_ = 0;
  std::uint64_t sequence_ = 0;
  ToolStyle style_;
};

}  // namespace vascsim::viewer
