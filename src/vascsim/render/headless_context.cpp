// The headless back-end of GlContext: EGL on Mesa's surfaceless platform, rendering into framebuffer
// objects. No display, no window system, no X server.

#include <dlfcn.h>
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <fmt/format.h>

#include <string>

#include "vascsim/render/gl_context.hpp"

namespace vascsim::render {

namespace {

std::string egl_error_name(EGLint e) {
  switch (e) {
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return fmt::format("EGL error 0x{:x}", e);
  }
}

class HeadlessContext final : public GlContext {
 public:
  explicit HeadlessContext(const ContextOptions& options) : width_(options.width), height_(options.height) {
    const char* hint =
        "; install EGL with Mesa's drivers (libegl1, libegl-mesa0, libgl1-mesa-dri) or open a window "
        "(set DISPLAY, or run under xvfb-run -a)";
    // libepoxy aborts the process when it cannot load libEGL.so.1: look for it first.
    if (void* egl = dlopen("libEGL.so.1", RTLD_LAZY | RTLD_LOCAL); egl != nullptr)
      dlclose(egl);
    else
      throw RenderSetupError(fmt::format("cannot render headless: libEGL.so.1 not found{}", hint));
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
      throw RenderSetupError(
          fmt::format("cannot render headless: no EGL with EGL_MESA_platform_surfaceless{}", hint));
    display_ = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display_ == EGL_NO_DISPLAY || eglInitialize(display_, &major, &minor) != EGL_TRUE)
      throw RenderSetupError(fmt::format("cannot render headless: EGL surfaceless display: {}{}",
                                         egl_error_name(eglGetError()), hint));
    try {
      if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) fail("this EGL has no desktop OpenGL", hint);
      const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                       EGL_NONE};
      EGLConfig config = nullptr;
      EGLint count = 0;
      if (eglChooseConfig(display_, config_attribs, &config, 1, &count) != EGL_TRUE || count < 1)
        config = nullptr;
      if (config == nullptr && !epoxy_has_egl_extension(display_, "EGL_KHR_no_config_context"))
        fail("no OpenGL config", hint);
      const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        3,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        3,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
      context_ = eglCreateContext(display_, config != nullptr ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT,
                                  context_attribs);
      if (context_ == EGL_NO_CONTEXT) fail("cannot create an OpenGL 3.3 core context", hint);
      if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE)
        fail("cannot make the surfaceless context current", hint);
      check_capabilities(options, "headless EGL");
      create_framebuffers(options.samples);
    } catch (...) {
      release();
      throw;
    }
  }
  ~HeadlessContext() override { release(); }

  ContextKind kind() const override { return ContextKind::headless; }
  void make_current() override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_); }
  unsigned draw_framebuffer() const override { return ms_fbo_ != 0 ? ms_fbo_ : fbo_; }
  unsigned read_framebuffer() const override { return fbo_; }
  std::array<int, 2> framebuffer_size() const override { return {width_, height_}; }
  void finish_frame() override {
    if (ms_fbo_ == 0) return;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, ms_fbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  void present() override { glFlush(); }

 private:
  [[noreturn]] void fail(const char* what, const char* hint) {
    throw RenderSetupError(
        fmt::format("cannot render headless: {}: {}{}", what, egl_error_name(eglGetError()), hint));
  }

  // A colour + depth framebuffer (multisampled if samples > 0) and the single-sampled one read back.
  void create_framebuffers(int samples) {
    auto make = [this](GLuint& fbo, GLuint(&rbs)[2], int s) {
      glGenFramebuffers(1, &fbo);
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glGenRenderbuffers(2, rbs);
      glBindRenderbuffer(GL_RENDERBUFFER, rbs[0]);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_RGBA8, width_, height_);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rbs[0]);
      glBindRenderbuffer(GL_RENDERBUFFER, rbs[1]);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_DEPTH24_STENCIL8, width_, height_);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, rbs[1]);
      const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
      if (status != GL_FRAMEBUFFER_COMPLETE)
        throw RenderSetupError(
            fmt::format("cannot render headless: a {}x{} framebuffer ({} samples) is incomplete "
                        "(status 0x{:x})",
                        width_, height_, s, status));
    };
    make(fbo_, rbs_, 0);
    if (samples > 0) make(ms_fbo_, ms_rbs_, samples);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  void release() {
    if (context_ != EGL_NO_CONTEXT) {
      if (fbo_ != 0) {
        glDeleteFramebuffers(1, &fbo_);
        glDeleteRenderbuffers(2, rbs_);
      }
      if (ms_fbo_ != 0) {
        glDeleteFramebuffers(1, &ms_fbo_);
        glDeleteRenderbuffers(2, ms_rbs_);
      }
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display_, context_);
      context_ = EGL_NO_CONTEXT;
    }
    if (display_ != EGL_NO_DISPLAY) {
      eglTerminate(display_);
      display_ = EGL_NO_DISPLAY;
    }
  }

  int width_, height_;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  GLuint fbo_ = 0, ms_fbo_ = 0;
  GLuint rbs_[2] = {0, 0}, ms_rbs_[2] = {0, 0};
};

}  // namespace

std::unique_ptr<GlContext> make_headless_context(const ContextOptions& options) {
  check_context_options(options);
  return std::make_unique<HeadlessContext>(options);
}

}  // namespace vascsim::render
