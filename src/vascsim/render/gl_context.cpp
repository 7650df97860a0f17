#include "vascsim/render/gl_context.hpp"

#include <algorithm>
#include <cstdlib>
#include <regex>

#include <epoxy/gl.h>
#include <fmt/format.h>

namespace vascsim::render {

void check_context_options(const ContextOptions& options) {
  if (options.width < 1 || options.height < 1 || options.width > kMaxFramebufferSize ||
      options.height > kMaxFramebufferSize)
    throw RenderSetupError(
        fmt::format("window size {}x{} is impossible: width and height must be 1 to {} pixels", options.width,
                    options.height, kMaxFramebufferSize));
  if (options.samples != 0 && options.samples != 2 && options.samples != 4 && options.samples != 8)
    throw RenderSetupError(
        fmt::format("multisampling {} is not supported: use 0, 2, 4 or 8", options.samples));
}

void parse_window_size(const std::string& text, const std::string& option, ContextOptions& options) {
  static const std::regex re(R"((-?\d{1,9})x(-?\d{1,9}))");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    throw RenderSetupError(
        fmt::format("{} {}: expected WIDTHxHEIGHT in pixels, e.g. 1280x800", option, text));
  options.width = std::stoi(m[1]);
  options.height = std::stoi(m[2]);
}

std::string GlContext::description() const {
  auto str = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s != nullptr ? s : "?");
  };
  return str(GL_RENDERER) + ", " + str(GL_VERSION);
}

void GlContext::check_capabilities(const ContextOptions& options, const char* back_end) const {
  const int version = epoxy_gl_version();  // 10 * major + minor
  if (version < 33)
    throw RenderSetupError(fmt::format("{}: OpenGL {}.{} found, 3.3 core or newer is needed ({})", back_end,
                                       version / 10, version % 10, description()));
  GLint dims[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
  GLint rb = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &rb);
  const int limit = std::min({dims[0], dims[1], static_cast<int>(rb)});
  if (options.width > limit || options.height > limit)
    throw RenderSetupError(
        fmt::format("window size {}x{} is impossible: this OpenGL ({}) allows at most {} pixels",
                    options.width, options.height, description(), limit));
}

bool display_available() {
  for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY"}) {
    const char* v = std::getenv(name);
    if (v != nullptr && *v != '\0') return true;
  }
  return false;
}

std::unique_ptr<GlContext> create_context(const ContextOptions& options) {
  check_context_options(options);
  if (options.headless || !display_available()) return make_headless_context(options);
  return make_window_context(options);
}

}  // namespace vascsim::render
