#pragma once
// Reading the finished frame back (glReadPixels, rows flipped to top-first) and writing it as a PNG; reading
// a PNG back.

#include <cstdint>
#include <string>
#include <vector>

namespace vascsim::render {

class GlContext;

/// 8-bit RGBA pixels, rows from the top of the picture.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
  const std::uint8_t* pixel(int x, int y) const {
    return &rgba[4 * (static_cast<std::size_t>(y) * width + x)];
  }
};

/// The frame in context.read_framebuffer() (call after GlContext::finish_frame(), before present()).
Image read_frame(const GlContext& context);

/// Writes `image` as an RGB PNG. Throws InputError naming the path if it cannot be written.
void write_png(const std::string& path, const Image& image);

/// Reads a PNG as 8-bit RGBA (tests, comparisons); an empty Image (width 0) if it cannot be read.
Image read_png(const std::string& path);

}  // namespace vascsim::render
