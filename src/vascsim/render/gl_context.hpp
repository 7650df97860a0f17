#pragma once
// An OpenGL (>= 3.3 core) context to render into, with two back-ends:
//  - a GLFW window (needs a display: X11 or Wayland, or Xvfb through xvfb-run);
//  - a headless EGL context on Mesa's surfaceless platform (EGL_MESA_platform_surfaceless, no display
//    and no window system at all), rendering into an offscreen framebuffer object.
// create_context() picks the headless one when asked to or when there is no display (neither DISPLAY
// nor WAYLAND_DISPLAY is set). Every GL and EGL entry point is loaded by libepoxy.
//
// Failures the user can act on (no display and no EGL, an impossible size) throw RenderSetupError, an
// InputError: the CLI prints its one-line message and exits with code 2.

#include <array>
#include <memory>
#include <string>

#include "vascsim/core/error.hpp"

struct GLFWwindow;

namespace vascsim::render {

class RenderSetupError : public InputError {
 public:
  using InputError::InputError;
};

enum class ContextKind { window, headless };

struct ContextOptions {
  int width = 1280, height = 800;  ///< window or offscreen framebuffer size, pixels
  std::string title = "vascsim";
  bool headless = false;  ///< force the EGL back-end even when a display exists
  bool visible = true;    ///< window back-end: show the window
  bool vsync = true;      ///< window back-end: swap interval 1
  int samples = 0;        ///< multisample anti-aliasing (0, 2, 4, 8)
};

/// Largest width or height accepted before any GL query (GL_MAX_VIEWPORT_DIMS is checked afterwards).
constexpr int kMaxFramebufferSize = 16384;

/// Throws RenderSetupError unless 1 <= width, height <= kMaxFramebufferSize and samples is 0, 2, 4 or 8.
void check_context_options(const ContextOptions& options);

/// Reads "WIDTHxHEIGHT" (e.g. "1280x800") into the options; throws RenderSetupError naming `option` for any
/// other text (the size itself is checked by check_context_options).
void parse_window_size(const std::string& text, const std::string& option, ContextOptions& options);

class GlContext {
 public:
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  virtual ContextKind kind() const = 0;
  virtual void make_current() = 0;
  /// The framebuffer object to draw the frame into (0: the window's back buffer).
  virtual unsigned draw_framebuffer() const = 0;
  /// The single-sampled framebuffer object that holds the finished frame for glReadPixels after
  /// finish_frame() (0: the window's back buffer, read before present()).
  virtual unsigned read_framebuffer() const = 0;
  /// Framebuffer size in pixels (a window's may differ from its size in screen coordinates).
  virtual std::array<int, 2> framebuffer_size() const = 0;
  /// Ends drawing a frame: resolves multisampling into read_framebuffer() (headless).
  virtual void finish_frame() {}
  /// Shows the frame (window: swap buffers; headless: nothing).
  virtual void present() = 0;
  /// The user closed the window (headless: never).
  virtual bool should_close() const { return false; }
  virtual void poll_events() {}
  virtual GLFWwindow* window() const { return nullptr; }

  /// "GL_RENDERER, GL_VERSION" of the current context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core
  /// Profile) Mesa 22.3.6".
  std::string description() const;

 protected:
  GlContext() = default;
  /// Throws RenderSetupError if the context is older than 3.3 or the size exceeds GL_MAX_VIEWPORT_DIMS or
  /// GL_MAX_RENDERBUFFER_SIZE. Call with the context current.
  void check_capabilities(const ContextOptions& options, const char* back_end) const;
};

/// A GLFW window with an OpenGL 3.3 core profile context (current on return).
std::unique_ptr<GlContext> make_window_context(const ContextOptions& options);
/// An EGL surfaceless context with an offscreen framebuffer (current on return).
std::unique_ptr<GlContext> make_headless_context(const ContextOptions& options);
/// Headless if options.headless or no display is set, else a window.
std::unique_ptr<GlContext> create_context(const ContextOptions& options);
/// True if DISPLAY or WAYLAND_DISPLAY is set and not empty.
bool display_available();

}  // namespace vascsim::render
