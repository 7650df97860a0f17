#pragma once
// An optional image for the wall (a scene may name one): loaded with stb_image into a mipmapped,
// repeating GL texture. The default wall texture is procedural (shaders.cpp) and needs no file.

#include <string>

namespace vascsim::render {

/// Reads PNG, JPEG, BMP or TGA. Throws InputError "texture file PATH: REASON" if the file is missing or
/// unreadable. Returns the GL texture name (the caller deletes it); needs a current context.
unsigned load_texture_file(const std::string& path);

}  // namespace vascsim::render
