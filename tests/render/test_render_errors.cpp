// Bad input gives one clear line and exit code 2, never a crash: an impossible size, no display and no
// EGL, a missing texture file. In-process (the exception) and through the demo program (the exit code).

#include <gtest/gtest.h>

#include <string>

#include "support/program_output.hpp"
#include "vascsim/render/gl_context.hpp"
#include "vascsim/render/renderer.hpp"

namespace vascsim::render {
namespace {

using Result = test::ProgramOutput;

Result run(const std::string& env, const std::string& args) {
  return test::run_program(env, VASCSIM_BINARY_DIR "/vascsim_render_demo", args);
}

TEST(RenderErrors, ImpossibleSizesThrowRenderSetupError) {
  for (auto [w, h] : {std::pair{0, 600}, {800, 0}, {-5, 10}, {100000, 100}, {20000, 20000}}) {
    ContextOptions o;
    o.width = w;
    o.height = h;
    o.headless = true;
    try {
      make_headless_context(o);
      FAIL() << w << "x" << h;
    } catch (const RenderSetupError& e) {
      EXPECT_NE(std::string(e.what()).find("impossible"), std::string::npos) << e.what();
    }
  }
  ContextOptions bad_msaa;
  bad_msaa.samples = 3;
  EXPECT_THROW(check_context_options(bad_msaa), RenderSetupError);
}

TEST(RenderErrors, MissingTextureThrowsInputErrorNamingTheFile) {
  ContextOptions o;
  o.width = 64;
  o.height = 64;
  o.headless = true;
  auto context = make_headless_context(o);
  Renderer renderer;
  try {
    renderer.set_wall_texture("no-such-dir/wall.png");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "texture file no-such-dir/wall.png: no such file");
  }
}

TEST(RenderErrors, DemoExitsWithCodeTwoAndOneLine) {
  const Result size = run("", "--headless --size 0x600 --out x.png");
  EXPECT_EQ(size.exit_code, 2) << size.output;
  EXPECT_EQ(size.lines(), 1u) << size.output;
  EXPECT_NE(size.output.find("window size 0x600 is impossible"), std::string::npos) << size.output;

  const Result huge = run("", "--headless --size 99999x99999");
  EXPECT_EQ(huge.exit_code, 2) << huge.output;
  EXPECT_EQ(huge.lines(), 1u) << huge.output;

  const Result garbage = run("", "--headless --size big");
  EXPECT_EQ(garbage.exit_code, 2) << garbage.output;
  EXPECT_EQ(garbage.lines(), 1u) << garbage.output;

  const Result texture = run("", "--headless --size 64x64 --texture missing-wall.png");
  EXPECT_EQ(texture.exit_code, 2) << texture.output;
  EXPECT_EQ(texture.lines(), 1u) << texture.output;
  EXPECT_NE(texture.output.find("texture file missing-wall.png: no such file"), std::string::npos);
}

TEST(RenderErrors, NoDisplayAndNoEglExitsWithCodeTwo) {
  // glvnd finds no EGL vendor when pointed at a file that does not exist: as on a machine without
  // Mesa's EGL. Without DISPLAY the demo must go headless, and fail with one line.
  const Result r =
      run("env -u DISPLAY -u WAYLAND_DISPLAY __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl.json",
          "--size 64x64 --out x.png");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.lines(), 1u) << r.output;
  EXPECT_NE(r.output.find("cannot render headless"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("xvfb-run"), std::string::npos) << r.output;
}

TEST(RenderErrors, WindowWithoutDisplayThrowsRenderSetupError) {
  // GLFW cannot open a window on a display that does not exist.
  const Result r = run("env DISPLAY=:987 WAYLAND_DISPLAY=", "--size 64x64 --frames 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.lines(), 1u) << r.output;
  EXPECT_NE(r.output.find("cannot open a window"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace vascsim::render
