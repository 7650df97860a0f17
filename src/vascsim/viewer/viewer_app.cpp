#include "vascsim/viewer/viewer_app.hpp"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <thread>

#include "vascsim/core/error.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/render/camera_controller.hpp"
#include "vascsim/render/screenshot.hpp"
#include "vascsim/scene/scene.hpp"
#include "vascsim/viewer/frame_builder.hpp"
#include "vascsim/viewer/frame_presenter.hpp"
#include "vascsim/viewer/session_panel.hpp"
#include "vascsim/viewer/window_input.hpp"

namespace vascsim::viewer {

namespace {

render::ContextOptions context_options(const ViewOptions& o) {
  render::ContextOptions co;
  render::parse_window_size(o.size, "--size", co);
  co.headless = o.headless || !o.screenshot.empty();
  co.samples = o.msaa;
  co.vsync = !o.measure;
  co.title = "vascsim view";
  render::check_context_options(co);
  return co;
}

render::HudControls initial_controls(const ViewOptions& o) {
  render::HudControls c;
  if (o.mode != "lit" && o.mode != "fluoro")
    throw InputError(fmt::format("--mode {}: use lit or fluoro", o.mode));
  c.mode = o.mode == "fluoro" ? render::ViewMode::fluoroscopy : render::ViewMode::lit;
  c.carm_lao_deg = static_cast<float>(o.lao_deg);
  c.carm_cranial_deg = static_cast<float>(o.cranial_deg);
  c.cutaway = o.cutaway;
  c.show_nodes = o.nodes;
  c.show_tets = o.tets;
  c.contrast_filled = !o.no_contrast;
  c.colour_field = o.stress_map   ? render::ColourField::stress
                   : o.colour_map ? render::ColourField::displacement
                                  : render::ColourField::none;
  c.paused = o.paused;
  return c;
}

LiveOptions live_options(const ViewOptions& o, bool lockstep) {
  LiveOptions l;
  l.lockstep = lockstep;
  if (!o.replay.empty()) {
    l.start = LiveCommand::Kind::replay;
    l.start_file = o.replay;
  } else if (o.play) {
    l.start = LiveCommand::Kind::play_trajectory;
  }
  return l;
}

// The bounds of the wall alone: the camera frames the vessel, not the display shaft of the catheter.
render::Bounds surface_bounds(const render::RenderFrame& f) {
  render::Bounds b;
  if (f.positions_m.empty()) return b;
  b.min = b.max = f.positions_m.front().cast<double>();
  for (const render::Float3& p : f.positions_m) {
    b.min = b.min.cwiseMin(p.cast<double>());
    b.max = b.max.cwiseMax(p.cast<double>());
  }
  return b;
}

// The fluoroscopy window that gives the contrast through the vessel's smallest side about one attenuation
// length (a 3 mm vein: 1.1, physical; a 25 mm aorta: 0.13; a 0.16 mm retinal artery: 21), within [0.05, 50].
double auto_window(const render::RenderFrame& frame) {
  const render::Bounds b = surface_bounds(frame);
  const double side = std::max((b.max - b.min).minCoeff(), 1e-9);
  return std::clamp(1.0 / (render::FluoroSettings{}.mu_contrast_per_m * side), 0.05, 50.0);
}

// Everything one viewer run holds. Members are destroyed in reverse order: the session (its threads) before
// what it writes into, the GL objects before the context.
class Viewer {
 public:
  Viewer(const ViewOptions& o, std::ostream& out)
      : options_(o),
        out_(out),
        scene_(load_scene(o.scene, o.sets)),
        context_(render::create_context(context_options(o))),
        headless_(context_->kind() == render::ContextKind::headless),
        lockstep_(headless_ && !o.realtime),
        controls_(initial_controls(o)),
        camera_(render::PatientFrame{scene_.viewer.superior, scene_.viewer.anterior}),
        renderer_(std::make_unique<render::Renderer>()),
        builder_(exchange_, mouse_, overlays_, !lockstep_) {
    if (!scene_.viewer.texture.empty())
      renderer_->set_wall_texture(scene_.viewer.texture, static_cast<float>(scene_.viewer.texture_repeats));
    session_ = std::make_unique<LiveSession>(scene_, mouse_, builder_, live_options(o, lockstep_));
    session_->set_paused(o.paused);
    presenter_ = std::make_unique<FramePresenter>(*context_, *renderer_, exchange_);
    presenter_->update(false);  // the rest state, published by the build
    camera_.fit(surface_bounds(presenter_->frame().render));
    camera_.enclose(render::frame_bounds(presenter_->frame().render));  // the tools reach out of the framing
    camera_.orbit(-o.yaw_deg / 0.3, (o.pitch_deg - 15.0) / 0.3);
    camera_.zoom(o.zoom);
    controls_.force_threshold_n = static_cast<float>(presenter_->frame().force_threshold_n);
    controls_.fluoro_window =
        static_cast<float>(o.fluoro_window > 0.0 ? o.fluoro_window : auto_window(presenter_->frame().render));
  }

  int run() { return headless_ ? run_headless() : run_window(); }

 private:
  void draw(bool with_hud, render::HudRequests* requests);
  void pace();
  void sync_from_controls();
  void write_screenshot(const std::string& path);
  int run_headless();
  int run_window();
  void report();

  ViewOptions options_;
  std::ostream& out_;
  Scene scene_;
  std::unique_ptr<render::GlContext> context_;
  bool headless_, lockstep_;
  render::HudControls controls_;
  render::RenderSettings settings_;
  render::OrbitCamera camera_;
  std::unique_ptr<render::Renderer> renderer_;
  FrameExchange<ViewerFrame> exchange_;
  OverlayRequests overlays_;
  MouseKeyboardDevice mouse_;
  FrameBuilder builder_;
  std::unique_ptr<LiveSession> session_;
  std::unique_ptr<FramePresenter> presenter_;
  std::unique_ptr<render::Hud> hud_;
  Stopwatch wall_;
  std::string ui_message_;  // the panel's own notice (a bad value), shown before the session's
  double fps_ = 0.0;
  SteadyClock::time_point last_frame_ = SteadyClock::now();
  SteadyClock::time_point frame_start_ = SteadyClock::now();
};

// The panel's choices that the simulation thread or the renderer reads.
void Viewer::sync_from_controls() {
  render::apply_controls(controls_, settings_);
  settings_.show_surface = !options_.no_surface;
  settings_.measure = options_.measure;
  overlays_.nodes.store(controls_.show_nodes, std::memory_order_relaxed);
  overlays_.tets.store(controls_.show_tets, std::memory_order_relaxed);
  overlays_.stress.store(controls_.colour_field == render::ColourField::stress, std::memory_order_relaxed);
  overlays_.force_threshold_n.store(controls_.force_threshold_n, std::memory_order_relaxed);
  // Tool input follows the picture: the axes of the view drawn (the C-arm's in fluoroscopy).
  mouse_.set_view(render::Renderer::pose_for(camera_, settings_).view_frame());
}

// One visual frame: the newest simulation frame (if any is new), the scene, the HUD.
void Viewer::draw(bool with_hud, render::HudRequests* requests) {
  const auto t0 = SteadyClock::now();
  sync_from_controls();
  presenter_->update(options_.measure);
  settings_.frame_index = static_cast<std::uint32_t>(presenter_->log().visual_frames());
  presenter_->draw(camera_, settings_);
  double hud_ms = 0.0;
  if (with_hud && hud_) {
    const auto t_hud = SteadyClock::now();
    const auto [w, h] = context_->framebuffer_size();
    hud_->begin_frame(w, h, seconds_between(last_frame_, t_hud));
    render::HudStats stats = presenter_->hud_stats(fps_);
    if (presenter_->frame().info.device == mouse_.name())
      stats.device_force_n = mouse_.last_sent_force().norm();
    if (!ui_message_.empty()) stats.message = ui_message_;
    const render::ScalarField* legend =
        presenter_->frame().render.scalar ? &*presenter_->frame().render.scalar : nullptr;
    const render::HudRequests r = hud_->draw(stats, controls_, legend);
    if (requests != nullptr) *requests = r;
    glBindFramebuffer(GL_FRAMEBUFFER, context_->draw_framebuffer());
    glViewport(0, 0, w, h);
    hud_->render();
    if (options_.measure) glFinish();
    hud_ms = 1e3 * seconds_since(t_hud);
  }
  context_->finish_frame();
  const auto now = SteadyClock::now();
  const double dt = std::max(seconds_between(last_frame_, now), 1e-6);
  last_frame_ = now;
  fps_ = fps_ == 0.0 ? 1.0 / dt : 0.9 * fps_ + 0.1 / dt;
  presenter_->log().visual_frame(1e3 * seconds_between(t0, now), presenter_->upload_ms(),
                                 renderer_->timing().draw_ms, hud_ms);
}

// Keeps the render thread to max_fps (lockstep pictures need no pacing: each frame waits for the model).
void Viewer::pace() {
  if (lockstep_ || options_.max_fps <= 0.0) return;
  const auto period = std::chrono::duration_cast<SteadyClock::duration>(
      std::chrono::duration<double>(1.0 / options_.max_fps));
  std::this_thread::sleep_until(frame_start_ + period);
  frame_start_ = SteadyClock::now();
}

void Viewer::write_screenshot(const std::string& path) {
  render::write_png(path, render::read_frame(*context_));
  out_ << fmt::format("wrote {}\n", path);
}

void Viewer::report() {
  if (!options_.measure) return;
  out_ << fmt::format("{} ({} nodes, {} triangles, model {}), {}x{} {}: {}\n", scene_.name,
                      presenter_->frame().nodes, renderer_->triangle_count(), presenter_->frame().model,
                      context_->framebuffer_size()[0], context_->framebuffer_size()[1], options_.mode,
                      presenter_->log().summary(wall_.seconds(), presenter_->frame().info.steps_per_s));
}

int Viewer::run_headless() {
  const int frames = std::max(options_.frames, 1);
  constexpr int kWarmupFrames = 10;  // shader compilation, first uploads, the model's first frames
  std::unique_ptr<SessionPanel> panel;
  if (options_.hud) {
    hud_ = std::make_unique<render::Hud>(*context_);
    panel = std::make_unique<SessionPanel>(*session_, scene_, options_.scene, options_.sets,
                                           controls_);  // choices
    draw(true, nullptr);  // ImGui sizes a new window in its first frame and shows it from the second
  }
  if (!lockstep_) session_->start();
  render::Image image;
  for (int i = 0; i < frames; ++i) {
    if (i == kWarmupFrames) presenter_->log().restart(wall_.seconds());
    if (lockstep_) session_->step_lockstep();  // frame i shows the state after i + 1 simulation frames
    pace();
    draw(options_.hud, nullptr);
    if (i == frames - 1 && !options_.screenshot.empty()) image = render::read_frame(*context_);
    context_->present();
  }
  if (!lockstep_) session_->stop();
  if (!image.rgba.empty()) {
    render::write_png(options_.screenshot, image);
    out_ << fmt::format("wrote {} ({} frames, t = {:.3f} s)\n", options_.screenshot, frames,
                        presenter_->frame().info.sample.sim_time_s);
  }
  if (options_.screenshot.empty() && !options_.measure)
    out_ << fmt::format(
        "{}: {} frame{} rendered headless ({}) and nothing kept: open a window with a display (or "
        "under xvfb-run -a), or write a picture with --screenshot FILE\n",
        scene_.name, frames, frames == 1 ? " was" : "s were",
        options_.headless ? "--headless" : "no display");
  if (!options_.fluoro_screenshot.empty()) {
    controls_.mode = render::ViewMode::fluoroscopy;  // the same frame again, as the C-arm sees it
    draw(options_.hud, nullptr);
    write_screenshot(options_.fluoro_screenshot);
  }
  report();
  return 0;
}

int Viewer::run_window() {
  render::CameraController controller(camera_);
  WindowInput input(context_->window(), controller, camera_, mouse_, controls_);
  hud_ = std::make_unique<render::Hud>(*context_);  // after the input: ImGui's callbacks chain to its own
  input.set_hud(hud_.get());
  SessionPanel panel(*session_, scene_, options_.scene, options_.sets, controls_);
  session_->start();
  bool show_hud = true;
  int shots = 0, done = 0;
  while (!context_->should_close() && (options_.frames == 0 || done < options_.frames)) {
    context_->poll_events();
    const KeyRequests keys = input.take();
    show_hud = show_hud != keys.toggle_hud;
    ui_message_ = panel.message();
    render::HudRequests requests;
    pace();
    draw(show_hud, &requests);
    if (requests.reset_camera) camera_.reset();
    if (requests.screenshot || keys.screenshot)
      write_screenshot(fmt::format("vascsim-{}-{:03d}.png", scene_.name, ++shots));
    panel.handle(requests, keys);
    context_->present();
    ++done;
  }
  session_->stop();
  report();
  return 0;
}

}  // namespace

int run_viewer(const ViewOptions& options, std::ostream& out) {
  Viewer viewer(options, out);
  return viewer.run();
}

}  // namespace vascsim::viewer
