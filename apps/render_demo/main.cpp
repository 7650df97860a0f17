// vascsim_render_demo: renders a swept vessel with a catheter (no simulation) in a window or headless,
// lit or fluoroscopic, and writes the last frame as a PNG. Also the renderer's timing harness.
//
//   vascsim_render_demo --out lit.png --frames 3 --size 1280x800
//   vascsim_render_demo --mode fluoro --lao 30 --out fluoro.png
//   vascsim_render_demo --triangles 100000 --frames 60 --measure      (timing split per frame)
//   vascsim_render_demo                                                 (a window, if there is a display)

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <deque>
#include <iostream>
#include <numeric>
#include <thread>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "vascsim/core/error.hpp"
#include "vascsim/render/camera_controller.hpp"
#include "vascsim/render/demo_vessel.hpp"
#include "vascsim/core/frame_exchange.hpp"
#include "vascsim/render/gl_context.hpp"
#include "vascsim/render/hud.hpp"
#include "vascsim/render/renderer.hpp"
#include "vascsim/render/screenshot.hpp"

namespace vr = vascsim::render;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
  std::string out;
  int frames = 0;  // 0: until the window is closed (1 when headless)
  std::string size = "1280x800";
  bool headless = false;
  std::string mode = "lit";
  double lao = 0.0, cranial = 0.0;
  int triangles = 20000;
  bool cutaway = false, colour_map = false, nodes = false, tets = false, hud = false, measure = false;
  bool no_contrast = false, no_force = false, no_surface = false;
  double force_scale = 1.0;
  std::string texture;
  int msaa = 0;
  double yaw = 0.0, pitch = 15.0, zoom = 0.0;
};

// Window input: the camera gets what the HUD does not want.
struct WindowInput {
  vr::CameraController* controller = nullptr;
  vr::Hud* hud = nullptr;
  bool fluoro_toggle = false;
};

void install_callbacks(GLFWwindow* window, WindowInput* input) {
  glfwSetWindowUserPointer(window, input);
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    if (action == GLFW_PRESS && in->hud != nullptr && in->hud->wants_mouse()) return;
    const vr::MouseButton b = button == GLFW_MOUSE_BUTTON_LEFT    ? vr::MouseButton::left
                              : button == GLFW_MOUSE_BUTTON_RIGHT ? vr::MouseButton::right
                                                                  : vr::MouseButton::middle;
    in->controller->button(b, action == GLFW_PRESS, (mods & GLFW_MOD_SHIFT) != 0, (mods & GLFW_MOD_CONTROL) != 0);
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    int fw = 0, fh = 0;
    glfwGetWindowSize(w, &fw, &fh);
    in->controller->cursor(x, y, fh);
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    if (in->hud != nullptr && in->hud->wants_mouse()) return;
    in->controller->scroll(dy);
  });
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    if (action != GLFW_PRESS || (in->hud != nullptr && in->hud->wants_keyboard())) return;
    if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(w, GLFW_TRUE);
    if (key == GLFW_KEY_F) in->fluoro_toggle = true;
    in->controller->key(key == GLFW_KEY_HOME ? vr::CameraController::kHome : key);
  });
}

// Median: robust to the other processes on a shared machine (a software renderer competes for the cores).
double mean(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}
double minimum(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

int run(const Options& o) {
  vr::ContextOptions co;
  vr::parse_window_size(o.size, "--size", co);
  co.headless = o.headless;
  co.samples = o.msaa;
  co.title = "vascsim render demo";
  co.vsync = !o.measure;
  vr::check_context_options(co);
  if (o.mode != "lit" && o.mode != "fluoro")
    throw vascsim::InputError(fmt::format("--mode {}: use lit or fluoro", o.mode));

  vr::DemoVesselSpec spec;
  spec.target_triangles = o.triangles;
  spec.overlays = o.nodes || o.tets;
  const auto t_build = Clock::now();
  const vr::DemoVessel demo(spec);
  const double build_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_build).count();

  auto context = vr::create_context(co);
  const bool headless = context->kind() == vr::ContextKind::headless;
  const int frames = o.frames > 0 ? o.frames : (headless ? 1 : 0);
  vr::Renderer renderer;
  if (!o.texture.empty()) renderer.set_wall_texture(o.texture);

  vr::RenderSettings settings;
  settings.measure = o.measure;
  vr::HudControls controls;
  controls.mode = o.mode == "fluoro" ? vr::ViewMode::fluoroscopy : vr::ViewMode::lit;
  controls.carm_lao_deg = static_cast<float>(o.lao);
  controls.carm_cranial_deg = static_cast<float>(o.cranial);
  controls.cutaway = o.cutaway;
  controls.show_nodes = o.nodes;
  controls.show_tets = o.tets;
  controls.show_force = !o.no_force;
  controls.contrast_filled = !o.no_contrast;
  controls.colour_field = o.colour_map ? vr::ColourField::displacement : vr::ColourField::none;
  controls.model = "demo (no simulation)";
  controls.model_choices = {controls.model};

  // Frames go through the same hand-off the viewer uses. Headless: filled on this thread before each
  // render (deterministic). Window: a producer thread publishes at about 120 Hz.
  vascsim::FrameExchange<vr::RenderFrame> exchange;
  std::uint64_t sequence = 0;
  auto produce = [&](double t) {
    vr::RenderFrame& f = exchange.back();
    demo.fill(f, t, o.force_scale);
    f.sequence = ++sequence;
    exchange.publish();
  };
  std::atomic<bool> stop{false};
  std::thread producer;
  if (!headless) {
    producer = std::thread([&] {
      const auto start = Clock::now();
      while (!stop.load(std::memory_order_relaxed)) {
        produce(0.2 * std::chrono::duration<double>(Clock::now() - start).count());
        std::this_thread::sleep_for(std::chrono::milliseconds(8));
      }
    });
  }

  vr::OrbitCamera camera;
  produce(0.25);
  exchange.update();
  camera.fit(vr::frame_bounds(exchange.front()));
  camera.orbit(-o.yaw / 0.3, (o.pitch - 15.0) / 0.3);
  camera.zoom(o.zoom);
  vr::CameraController controller(camera);
  WindowInput input{&controller, nullptr};
  if (!headless) install_callbacks(context->window(), &input);
  std::unique_ptr<vr::Hud> hud;
  if (o.hud || !headless) {
    hud = std::make_unique<vr::Hud>(*context);
    input.hud = hud.get();
  }

  std::vector<double> upload_ms, draw_ms, hud_ms, frame_ms, produce_ms;
  std::deque<float> force_history;
  std::uint64_t uploaded_sequence = 0;
  auto last = Clock::now();
  double fps = 0.0;
  int done = 0;
  vr::Image image;
  while (true) {
    if (frames > 0 && done >= frames) break;
    if (!headless) {
      context->poll_events();
      if (context->should_close()) break;
    }
    if (input.fluoro_toggle) {
      controls.mode = controls.mode == vr::ViewMode::lit ? vr::ViewMode::fluoroscopy : vr::ViewMode::lit;
      input.fluoro_toggle = false;
    }
    if (headless) {
      // The producer's share (positions and normals of the next surface): the simulation thread's cost.
      const auto t_produce = Clock::now();
      produce(0.25 + 0.013 * (done - (frames - 1)));
      produce_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t_produce).count());
    }
    const auto t_frame = Clock::now();
    exchange.update();
    const vr::RenderFrame& frame = exchange.front();
    if (frame.sequence != uploaded_sequence) {
      renderer.upload(frame, o.measure);
      uploaded_sequence = frame.sequence;
      upload_ms.push_back(renderer.timing().upload_ms);
    }
    apply_controls(controls, settings);
    settings.show_surface = !o.no_surface;
    settings.frame_index = static_cast<std::uint32_t>(done);
    const auto [w, h] = context->framebuffer_size();
    renderer.draw(camera, settings, context->draw_framebuffer(), w, h);
    draw_ms.push_back(renderer.timing().draw_ms);
    if (hud) {
      const auto t_hud = Clock::now();
      const float force = frame.force ? frame.force->force_n.norm() : 0.0f;
      force_history.push_back(force);
      if (force_history.size() > 240) force_history.pop_front();
      vr::HudStats stats;
      stats.visual_fps = fps;
      stats.tool_force_n = force;
      stats.force_threshold_n = frame.force ? frame.force->threshold_n : 0.0;
      stats.force_history_n.assign(force_history.begin(), force_history.end());
      stats.nodes = demo.vessel().cloud.positions.size();
      stats.triangles = frame.triangles.size();
      stats.model_name = "demo vessel (no simulation)";
      stats.sim_time_s = frame.sim_time_s;
      stats.upload_ms = renderer.timing().upload_ms;
      stats.draw_ms = renderer.timing().draw_ms;
      stats.gl_renderer = context->description();
      const double dt = std::chrono::duration<double>(Clock::now() - last).count();
      hud->begin_frame(w, h, dt);
      const vr::HudRequests requests =
          hud->draw(stats, controls, settings.show_colour_map && frame.scalar ? &*frame.scalar : nullptr);
      if (requests.reset_camera) camera.reset();
      glBindFramebuffer(GL_FRAMEBUFFER, context->draw_framebuffer());
      glViewport(0, 0, w, h);
      hud->render();
      if (o.measure) glFinish();
      hud_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t_hud).count());
    }
    context->finish_frame();
    ++done;
    if (!o.out.empty() && frames > 0 && done == frames) image = vr::read_frame(*context);
    context->present();
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    fps = fps == 0.0 ? 1.0 / std::max(dt, 1e-6) : 0.9 * fps + 0.1 / std::max(dt, 1e-6);
    frame_ms.push_back(std::chrono::duration<double, std::milli>(now - t_frame).count());
  }
  stop = true;
  if (producer.joinable()) producer.join();
  if (!o.out.empty() && !image.rgba.empty()) vr::write_png(o.out, image);

  // Timing: the first frame compiles and allocates; report the median of the rest (and the draw minimum).
  auto tail = [](std::vector<double> v) {
    if (v.size() > 1) v.erase(v.begin());
    return v;
  };
  std::cout << fmt::format(
      "{} {}x{} {} | {} triangles, {} vertices | build {:.0f} ms | frames {} | median: upload {:.2f} ms, draw {:.2f} ms "
      "(min {:.2f}){}, "
      "frame {:.2f} ms ({:.1f} fps){}{}\n",
      context->kind() == vr::ContextKind::headless ? "headless" : "window", co.width, co.height, o.mode,
      renderer.triangle_count(), renderer.vertex_count(), build_ms, done, mean(tail(upload_ms)), mean(tail(draw_ms)),
      minimum(tail(draw_ms)), hud_ms.empty() ? std::string() : fmt::format(", hud {:.2f} ms", mean(tail(hud_ms))), mean(tail(frame_ms)),
      1000.0 / std::max(mean(tail(frame_ms)), 1e-9), o.measure ? " [glFinish per phase]" : "",
      produce_ms.empty() ? std::string() : fmt::format(" | surface prepared in {:.2f} ms (producer)", mean(tail(produce_ms))));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vascsim render demo: a swept vessel and a catheter, rendered without simulation"};
  Options o;
  app.add_option("--out", o.out, "Write the last frame as a PNG");
  app.add_option("--frames", o.frames, "Frames to render (default: 1 headless, until closed in a window)");
  app.add_option("--size", o.size, "Framebuffer size WIDTHxHEIGHT (default 1280x800)");
  app.add_flag("--headless", o.headless, "Render offscreen through EGL even when a display exists");
  app.add_option("--mode", o.mode, "lit or fluoro");
  app.add_option("--lao", o.lao, "Fluoroscopy: C-arm LAO (+) / RAO (-) angle, degrees");
  app.add_option("--cranial", o.cranial, "Fluoroscopy: C-arm cranial (+) / caudal (-) angle, degrees");
  app.add_option("--triangles", o.triangles, "About this many wall triangles (default 20000)");
  app.add_flag("--cutaway", o.cutaway, "Cut away the near half of the wall");
  app.add_flag("--colour-map", o.colour_map, "Colour the wall by the (synthetic) displacement");
  app.add_flag("--nodes", o.nodes, "Show the node cloud");
  app.add_flag("--tets", o.tets, "Show the virtual tetrahedra");
  app.add_flag("--hud", o.hud, "Draw the HUD panel headless too");
  app.add_flag("--measure", o.measure, "glFinish between upload and draw for an honest time split");
  app.add_flag("--no-contrast", o.no_contrast, "Fluoroscopy without contrast in the lumen");
  app.add_flag("--no-force", o.no_force, "Hide the force arrow");
  app.add_flag("--no-surface", o.no_surface, "Do not draw the wall (to check the tests catch it)");
  app.add_option("--force-scale", o.force_scale, "Scale of the indentation and force (1: 0.4 N, threshold 0.5 N)");
  app.add_option("--texture", o.texture, "Wall texture image instead of the procedural one");
  app.add_option("--msaa", o.msaa, "Multisampling: 0, 2, 4, 8");
  app.add_option("--yaw", o.yaw, "Lit view: camera yaw, degrees (0: from the front)");
  app.add_option("--pitch", o.pitch, "Lit view: camera pitch, degrees (default 15)");
  app.add_option("--zoom", o.zoom, "Zoom notches (positive: closer)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    return run(o);
  } catch (const vascsim::InputError& e) {
    std::cerr << "vascsim_render_demo: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "vascsim_render_demo: internal error: " << e.what() << "\n";
    return 1;
  }
}
