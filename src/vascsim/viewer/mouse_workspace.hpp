#pragma once
// The mouse/keyboard device (interaction/mouse_keyboard_device.hpp) fitted to a scene: it starts at the
// tool's rest pose (a catheter pointing as the scene says; it no longer follows the camera), its workspace
// spans the scene, and its gains scale
// with the scene so a vein (20 mm) and a retinal artery (under a millimetre) are both steerable.

#include <cstddef>

#include "vascsim/interaction/mouse_keyboard_device.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim::viewer {

/// Settings for driving tool `tool` of `scene` whose surface has bounding radius `scene_radius_m`:
/// workspace centred on the tool point with twice that radius; a 400-pixel drag moves the tool by the scene
/// radius; a scroll notch advances 1/40 of it; a held key advances it in 4 s.
MouseKeyboardSettings mouse_settings(const Scene& scene, std::size_t tool, double scene_radius_m);

}  // namespace vascsim::viewer
