#pragma once
// The colour map of the scalar overlay (displacement, stress): one definition for the shader and the
// legend, so the two always agree. Five stops from dark blue (low) through teal, green and yellow to
// red (high), sRGB.

#include <string>

#include "vascsim/render/render_frame.hpp"

namespace vascsim::render {

/// sRGB colour of t in [0, 1] (clamped).
Float3 colour_map(float t);
/// GLSL source of `vec3 colour_map(float t)` with the same stops (sRGB).
std::string colour_map_glsl();

}  // namespace vascsim::render
