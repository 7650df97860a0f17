#pragma once
// The mouse/keyboard device (interaction/mouse_keyboard_device.hpp) fitted to a scene: it starts at the
// tool's rest pose (a catheter pointing as the scene says; it no longer follows the camera), its workspace
// spans the scene, and its gains scale
// with the scene so a vein (20 mm) and a retinal artery (under a millimetre) are both steerable.

#include <cstddef>

#include "vascsim/interaction/mouse_keyboard_device.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim::viewer {

/// Settings for driving tool `tool` of `scene` whose rest surface spans `lo` to `hi` (m): the workspace is
/// centred on the tool point with the diagonal of that box as its radius; the gains follow the box's smallest
/// side s (a vessel's diameter): a 100-pixel drag moves the tool s/3, a scroll notch advances it s/30, a held
/// key advances it s/3 per second (a 3 mm vein: 1 mm/s, the speed of the scripted press).
MouseKeyboardSettings mouse_settings(const Scene& scene, std::size_t tool, const Vec3& lo, const Vec3& hi);

}  // namespace vascsim::viewer
