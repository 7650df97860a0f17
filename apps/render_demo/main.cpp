// vascsim_render_demo: renders a swept vessel with a catheter (no simulation) in a window or headless,
// lit or fluoroscopic, and writes the last frame as a PNG. Also the renderer's timing harness.
//
//   vascsim_render_demo --out lit.png --frames 3 --size 1280x800
//   vascsim_render_demo --mode fluoro --lao 30 --out fluoro.png
//   vascsim_render_demo --triangles 100000 --frames 60 --measure      (timing split per frame)
//   vascsim_render_demo                                                 (a window, if there is a display)

#include <fmt/format.h>
#include <CLI/CLI.hpp>

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
#include "vascsim/core/frame_exchange.hpp"
#include "vascsim/render/camera_controller.hpp"
#include "vascsim/render/demo_vessel.hpp"
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
    in->controller->button(b, action == GLFW_PRESS, (mods & GLFW_MOD_SHIFT) != 0,
                           (mods & GLFW_MOD_CONTROL) != 0);
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
double minimum(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
}

vr::ContextOptions context_options(const Options& o) {
  vr::ContextOptions co;
  vr::parse_window_size(o.size, "--size", co);
  co.headless = o.headless;
  co.samples = o.msaa;
  co.title = "vascsim render demo";
  co.vsync = !o.measure;
  vr::check_context_options(co);
  if (o.mode != "lit" && o.mode != "fluoro")
    throw vascsim::InputError(fmt::format("--mode {}: use lit or fluoro", o.mode));
  return co;
}

vr::DemoVesselSpec demo_spec(const Options& o) {
  vr::DemoVesselSpec spec;
  spec.target_triangles = o.triangles;
  spec.overlays = o.nodes || o.tets;
  return spec;
}

vr::HudControls demo_controls(const Options& o) {
  vr::HudControls c;
  c.mode = o.mode == "fluoro" ? vr::ViewMode::fluoroscopy : vr::ViewMode::lit;
  c.carm_lao_deg = static_cast<float>(o.lao);
  c.carm_cranial_deg = static_cast<float>(o.cranial);
  c.cutaway = o.cutaway;
  c.show_nodes = o.nodes;
  c.show_tets = o.tets;
  c.show_force = !o.no_force;
  c.contrast_filled = !o.no_contrast;
  c.colour_field = o.colour_map ? vr::ColourField::displacement : vr::ColourField::none;
  c.model = "demo (no simulation)";
  c.model_choices = {c.model};
  return c;
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The demo: the vessel, a context, the renderer and the frame hand-off the viewer uses. Headless, frames are
// filled on this thread before each render (deterministic); in a window a producer thread publishes at about
// 120 Hz.
class Demo {
 public:
  explicit Demo(const Options& o)
      : o_(o),
        co_(context_options(o)),
        build_start_(Clock::now()),
        demo_(demo_spec(o)),
        build_ms_(ms_since(build_start_)),
        context_(vr::create_context(co_)),
        headless_(context_->kind() == vr::ContextKind::headless),
        frames_(o.frames > 0 ? o.frames : (headless_ ? 1 : 0)),
        controls_(demo_controls(o)),
        controller_(camera_) {
    renderer_ = std::make_unique<vr::Renderer>();
    if (!o.texture.empty()) renderer_->set_wall_texture(o.texture);
    settings_.measure = o.measure;
    produce(0.25);
    exchange_.update();
    camera_.fit(vr::frame_bounds(exchange_.front()));
    camera_.orbit(-o.yaw / 0.3, (o.pitch - 15.0) / 0.3);
    camera_.zoom(o.zoom);
    if (!headless_) install_callbacks(context_->window(), &input_);
    if (o.hud || !headless_) {
      hud_ = std::make_unique<vr::Hud>(*context_);
      input_.hud = hud_.get();
    }
  }

  int run() {
    if (!headless_) start_producer();
    vr::Image image;
    for (int done = 0; frames_ == 0 || done < frames_; ++done) {
      if (!headless_) {
        context_->poll_events();
        if (context_->should_close()) break;
      }
      if (input_.fluoro_toggle) {
        controls_.mode = controls_.mode == vr::ViewMode::lit ? vr::ViewMode::fluoroscopy : vr::ViewMode::lit;
        input_.fluoro_toggle = false;
      }
      draw_frame(done);
      if (!o_.out.empty() && frames_ > 0 && done + 1 == frames_) image = vr::read_frame(*context_);
      context_->present();
    }
    stop_ = true;
    if (producer_.joinable()) producer_.join();
    if (!o_.out.empty() && !image.rgba.empty()) vr::write_png(o_.out, image);
    report();
    return 0;
  }

 private:
  void produce(double t) {
    vr::RenderFrame& f = exchange_.back();
    demo_.fill(f, t, o_.force_scale);
    f.sequence = ++sequence_;
    exchange_.publish();
  }

  void start_producer() {
    producer_ = std::thread([this] {
      const auto start = Clock::now();
      while (!stop_.load(std::memory_order_relaxed)) {
        produce(0.2 * std::chrono::duration<double>(Clock::now() - start).count());
        std::this_thread::sleep_for(std::chrono::milliseconds(8));
      }
    });
  }

  // One frame: (headless) the next surface, upload when new, draw, HUD.
  void draw_frame(int done) {
    if (headless_) {
      // The producer's share (positions and normals of the next surface): the simulation thread's cost.
      const auto t_produce = Clock::now();
      produce(0.25 + 0.013 * (done - (frames_ - 1)));
      produce_ms_.push_back(ms_since(t_produce));
    }
    const auto t_frame = Clock::now();
    exchange_.update();
    const vr::RenderFrame& frame = exchange_.front();
    if (frame.sequence != uploaded_sequence_) {
      renderer_->upload(frame, o_.measure);
      uploaded_sequence_ = frame.sequence;
      upload_ms_.push_back(renderer_->timing().upload_ms);
    }
    apply_controls(controls_, settings_);
    settings_.show_surface = !o_.no_surface;
    settings_.frame_index = static_cast<std::uint32_t>(done);
    const auto [w, h] = context_->framebuffer_size();
    renderer_->draw(camera_, settings_, context_->draw_framebuffer(), w, h);
    draw_ms_.push_back(renderer_->timing().draw_ms);
    if (hud_) draw_hud(frame, w, h);
    context_->finish_frame();
    const auto now = Clock::now();
    const double dt = std::max(std::chrono::duration<double>(now - last_).count(), 1e-6);
    last_ = now;
    fps_ = fps_ == 0.0 ? 1.0 / dt : 0.9 * fps_ + 0.1 / dt;
    frame_ms_.push_back(std::chrono::duration<double, std::milli>(now - t_frame).count());
  }

  void draw_hud(const vr::RenderFrame& frame, int w, int h) {
    const auto t_hud = Clock::now();
    const float force = frame.force ? frame.force->force_n.norm() : 0.0f;
    force_history_.push_back(force);
    if (force_history_.size() > 240) force_history_.pop_front();
    vr::HudStats stats;
    stats.visual_fps = fps_;
    stats.tool_force_n = force;
    stats.force_threshold_n = frame.force ? frame.force->threshold_n : 0.0;
    stats.force_history_n.assign(force_history_.begin(), force_history_.end());
    stats.nodes = demo_.vessel().cloud.positions.size();
    stats.triangles = frame.triangles.size();
    stats.model_name = "demo vessel (no simulation)";
    stats.sim_time_s = frame.sim_time_s;
    stats.upload_ms = renderer_->timing().upload_ms;
    stats.draw_ms = renderer_->timing().draw_ms;
    stats.gl_renderer = context_->description();
    hud_->begin_frame(w, h, std::chrono::duration<double>(Clock::now() - last_).count());
    const vr::HudRequests requests =
        hud_->draw(stats, controls_, settings_.show_colour_map && frame.scalar ? &*frame.scalar : nullptr);
    if (requests.reset_camera) camera_.reset();
    glBindFramebuffer(GL_FRAMEBUFFER, context_->draw_framebuffer());
    glViewport(0, 0, w, h);
    hud_->render();
    if (o_.measure) glFinish();
    hud_ms_.push_back(ms_since(t_hud));
  }

  // Timing: the first frame compiles and allocates; report the median of the rest (and the draw minimum).
  void report() const {
    auto tail = [](std::vector<double> v) {
      if (v.size() > 1) v.erase(v.begin());
      return v;
    };
    std::cout << fmt::format(
        "{} {}x{} {} | {} triangles, {} vertices | build {:.0f} ms | frames {} | median: upload {:.2f} ms, "
        "draw "
        "{:.2f} ms (min {:.2f}){}, frame {:.2f} ms ({:.1f} fps){}{}\n",
        headless_ ? "headless" : "window", co_.width, co_.height, o_.mode, renderer_->triangle_count(),
        renderer_->vertex_count(), build_ms_, frame_ms_.size(), mean(tail(upload_ms_)), mean(tail(draw_ms_)),
        minimum(tail(draw_ms_)),
        hud_ms_.empty() ? std::string() : fmt::format(", hud {:.2f} ms", mean(tail(hud_ms_))),
        mean(tail(frame_ms_)), 1000.0 / std::max(mean(tail(frame_ms_)), 1e-9),
        o_.measure ? " [glFinish per phase]" : "",
        produce_ms_.empty()
            ? std::string()
            : fmt::format(" | surface prepared in {:.2f} ms (producer)", mean(tail(produce_ms_))));
  }

  const Options& o_;
  vr::ContextOptions co_;
  Clock::time_point build_start_;
  const vr::DemoVessel demo_;
  double build_ms_;
  std::unique_ptr<vr::GlContext> context_;
  bool headless_;
  int frames_;
  std::unique_ptr<vr::Renderer> renderer_;
  vr::RenderSettings settings_;
  vr::HudControls controls_;
  vascsim::FrameExchange<vr::RenderFrame> exchange_;
  std::uint64_t sequence_ = 0, uploaded_sequence_ = 0;
  std::atomic<bool> stop_{false};
  std::thread producer_;
  vr::OrbitCamera camera_;
  vr::CameraController controller_;
  WindowInput input_{&controller_, nullptr};
  std::unique_ptr<vr::Hud> hud_;
  std::vector<double> upload_ms_, draw_ms_, hud_ms_, frame_ms_, produce_ms_;
  std::deque<float> force_history_;
  Clock::time_point last_ = Clock::now();
  double fps_ = 0.0;
};

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
  app.add_option("--force-scale", o.force_scale,
                 "Scale of the indentation and force (1: 0.4 N, threshold 0.5 N)");
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
    return Demo(o).run();
  } catch (const vascsim::InputError& e) {
    std::cerr << "vascsim_render_demo: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "vascsim_render_demo: internal error: " << e.what() << "\n";
    return 1;
  }
}
