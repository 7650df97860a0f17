// The GLFW window back-end of GlContext.

#include <epoxy/gl.h>
// epoxy provides the GL declarations; GLFW must not include its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <mutex>
#include <string>

#include "vascsim/render/gl_context.hpp"

namespace vascsim::render {

namespace {

std::mutex g_error_mutex;
std::string g_last_error;  // the last GLFW error message (GLFW reports errors through a callback)

void on_glfw_error(int code, const char* description) {
  std::lock_guard lock(g_error_mutex);
  g_last_error = fmt::format("{} (GLFW error 0x{:x})", description != nullptr ? description : "?", code);
}

std::string last_error() {
  std::lock_guard lock(g_error_mutex);
  return g_last_error.empty() ? std::string("no reason given") : g_last_error;
}

class WindowContext final : public GlContext {
 public:
  explicit WindowContext(const ContextOptions& options) {
    glfwSetErrorCallback(on_glfw_error);
    if (glfwInit() != GLFW_TRUE)
      throw RenderSetupError(
          fmt::format("cannot open a window: {}; render headless instead (--headless, EGL) or "
                      "run under xvfb-run -a",
                      last_error()));
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SAMPLES, options.samples);
    glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    window_ = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
    if (window_ == nullptr) {
      const std::string reason = last_error();
      glfwTerminate();
      throw RenderSetupError(fmt::format("cannot open a {}x{} window with OpenGL 3.3 core: {}", options.width,
                                         options.height, reason));
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(options.vsync ? 1 : 0);
    try {
      check_capabilities(options, "window");
    } catch (...) {
      glfwDestroyWindow(window_);
      glfwTerminate();
      throw;
    }
  }
  ~WindowContext() override {
    glfwDestroyWindow(window_);
    glfwTerminate();
  }

  ContextKind kind() const override { return ContextKind::window; }
  void make_current() override { glfwMakeContextCurrent(window_); }
  unsigned draw_framebuffer() const override { return 0; }
  unsigned read_framebuffer() const override { return 0; }
  std::array<int, 2> framebuffer_size() const override {
    std::array<int, 2> s{0, 0};
    glfwGetFramebufferSize(window_, &s[0], &s[1]);
    return s;
  }
  void present() override { glfwSwapBuffers(window_); }
  bool should_close() const override { return glfwWindowShouldClose(window_) == GLFW_TRUE; }
  void poll_events() override { glfwPollEvents(); }
  GLFWwindow* window() const override { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> make_window_context(const ContextOptions& options) {
  check_context_options(options);
  return std::make_unique<WindowContext>(options);
}

}  // namespace vascsim::render
