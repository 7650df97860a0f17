#include "vascsim/viewer/navigation_pictures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/render/camera.hpp"
#include "vascsim/render/gl_context.hpp"
#include "vascsim/render/screenshot.hpp"
#include "vascsim/run/body_builder.hpp"
#include "vascsim/viewer/surface_snapshot.hpp"

namespace vascsim::viewer {

namespace {

constexpr int kWidth = 1280, kHeight = 800;

// The bounds of the wall alone: the camera frames the vessel, the proximal part of the instrument outside
// it may leave the picture.
render::Bounds wall_bounds(const render::RenderFrame& f) {
  render::RenderFrame wall;
  wall.positions_m = f.positions_m;
  return render::scene_bounds(wall);
}

render::Image draw(render::GlContext& context, render::Renderer& renderer, const render::OrbitCamera& camera,
                   const render::RenderSettings& settings) {
  renderer.draw(camera, settings, context.draw_framebuffer(), kWidth, kHeight);
  context.finish_frame();
  return render::read_frame(context);
}

}  // namespace

render::RenderFrame navigation_frame(const Scene& scene, const NavigationResult& result) {
  const Body body = build_body(scene.geometry);
  if (!body.surface)
    throw InputError(
        fmt::format("{}: geometry '{}' has no wall surface to draw", scene.file, scene.geometry.type));
  render::RenderFrame frame;
  fill_rest_surface(*body.surface, scene.viewer.superior, frame);
  render::InstrumentTube tube;
  for (const Vec3& x : result.final_positions_m) tube.centreline_m.push_back(x.cast<float>());
  if (scene.instrument) tube.radius_m = static_cast<float>(0.5 * scene.instrument->section.outer_diameter_m);
  frame.instruments.push_back(std::move(tube));
  frame.sequence = 1;
  return frame;
}

render::FluoroSettings navigation_fluoroscopy(double instrument_diameter_m) {
  render::FluoroSettings f;
  f.contrast_filled = false;
  // exp(-1.6) = 0.2 through the instrument's diameter; the window stays in the viewer's range.
  const double window =
      std::clamp(1.6 / (f.mu_tool_per_m * std::max(instrument_diameter_m, 1e-6)), 0.05, 50.0);
  f.mu_tissue_per_m *= static_cast<float>(window);
  f.mu_contrast_per_m *= static_cast<float>(window);
  f.mu_tool_per_m *= static_cast<float>(window);
  return f;
}

void write_navigation_pictures(const Scene& scene, const NavigationResult& result,
                               const std::filesystem::path& out_dir, std::ostream& out) {
  const render::RenderFrame frame = navigation_frame(scene, result);
  render::ContextOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.headless = true;
  options.samples = 4;  // the wire is a few pixels wide: smooth its edges
  std::unique_ptr<render::GlContext> context;
  try {
    context = render::make_headless_context(options);
  } catch (const render::RenderSetupError& e) {
    throw render::RenderSetupError(
        fmt::format("--pictures: {} (the navigation's other files are written)", e.what()));
  }
  render::Renderer renderer;
  if (!scene.viewer.texture.empty())
    renderer.set_wall_texture(scene.viewer.texture, static_cast<float>(scene.viewer.texture_repeats));
  renderer.upload(frame);
  render::OrbitCamera camera(render::PatientFrame{scene.viewer.superior, scene.viewer.anterior});
  camera.fit(wall_bounds(frame));
  camera.enclose(render::frame_bounds(frame));  // the instrument's proximal part stays inside the clip range

  std::filesystem::create_directories(out_dir);
  render::RenderSettings lit;
  lit.cutaway = true;
  const std::filesystem::path lit_file = out_dir / "navigation_lit.png";
  render::write_png(lit_file.string(), draw(*context, renderer, camera, lit));
  out << fmt::format("wrote {}\n", lit_file.string());

  render::RenderSettings fluoro;
  fluoro.mode = render::ViewMode::fluoroscopy;
  fluoro.fluoro =
      navigation_fluoroscopy(scene.instrument ? scene.instrument->section.outer_diameter_m : 1e-3);
  const std::filesystem::path fluoro_file = out_dir / "navigation_fluoroscopy.png";
  render::write_png(fluoro_file.string(), draw(*context, renderer, camera, fluoro));
  out << fmt::format("wrote {}\n", fluoro_file.string());
}

void install_navigation_pictures(CLI::App& /*app*/, CliContext& ctx, std::vector<Command>& /*commands*/) {
  ctx.navigation_pictures = &write_navigation_pictures;
}

}  // namespace vascsim::viewer
