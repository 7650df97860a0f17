#pragma once
// The panel's link to the live session (UI thread): it fills the panel's choices and editable values from the
// scene shown, and turns the panel's and the keyboard's requests into session commands. A new scene, another
// model, or edited material and solver settings are a scene read again with overrides (as `--set`), checked
// here, and rebuilt by the simulation thread; a bad value is a message in the panel, never a crash.

#include <string>
#include <vector>

#include "vascsim/render/hud.hpp"
#include "vascsim/run/live_session.hpp"
#include "vascsim/viewer/window_input.hpp"

namespace vascsim::viewer {

class SessionPanel {
 public:
  /// `scene` was read from `path` with the command line's `overrides`; `controls` is the panel's state.
  SessionPanel(LiveSession& session, const Scene& scene, std::string path, std::vector<std::string> overrides,
               render::HudControls& controls);

  /// Acts on this frame's requests (not the camera's or the screenshot's: the viewer's).
  void handle(const render::HudRequests& panel, const KeyRequests& keys);
  /// The latest problem with what the user chose ("" : none); the session reports its own.
  const std::string& message() const { return message_; }

 private:
  void show(const Scene& scene);
  void reload(const std::string& path, const std::vector<std::string>& overrides, bool keep_edits);
  std::vector<std::string> edited_overrides() const;

  LiveSession& session_;
  render::HudControls& controls_;
  std::string path_;                    // the scene file shown
  std::vector<std::string> overrides_;  // the command line's (for its own scene only)
  Scene file_scene_;                    // as read with overrides_ only: what the edits are compared with
  std::string message_;
};

}  // namespace vascsim::viewer
