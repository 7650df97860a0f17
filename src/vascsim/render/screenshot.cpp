#include "vascsim/render/screenshot.hpp"

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <cstring>

#include "vascsim/core/error.hpp"
#include "vascsim/render/gl_context.hpp"

namespace vascsim::render {

Image read_frame(const GlContext& context) {
  const auto [w, h] = context.framebuffer_size();
  Image image;
  image.width = w;
  image.height = h;
  image.rgba.resize(static_cast<std::size_t>(w) * h * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, context.read_framebuffer());
  if (context.read_framebuffer() == 0) glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  // GL rows start at the bottom.
  const std::size_t row = static_cast<std::size_t>(w) * 4;
  std::vector<std::uint8_t> tmp(row);
  for (int y = 0; y < h / 2; ++y) {
    std::uint8_t* a = &image.rgba[y * row];
    std::uint8_t* b = &image.rgba[(h - 1 - y) * row];
    std::memcpy(tmp.data(), a, row);
    std::memcpy(a, b, row);
    std::memcpy(b, tmp.data(), row);
  }
  return image;
}

void write_png(const std::string& path, const Image& image) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(image.width) * image.height * 3);
  for (std::size_t i = 0, n = rgb.size() / 3; i < n; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = image.rgba[4 * i + c];
  if (stbi_write_png(path.c_str(), image.width, image.height, 3, rgb.data(), image.width * 3) == 0)
    throw InputError(fmt::format("cannot write the screenshot {}", path));
}

Image read_png(const std::string& path) {
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  Image image;
  if (data == nullptr) return image;
  image.width = w;
  image.height = h;
  image.rgba.assign(data, data + static_cast<std::size_t>(4) * w * h);
  stbi_image_free(data);
  return image;
}

}  // namespace vascsim::render
