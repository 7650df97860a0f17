// `vascsim view SCENE.json [--set k=v ...]`: the interactive viewer (docs/viewer.md);
// `vascsim view SCENE.json --screenshot out.png --frames N [--size WxH]`: a picture without a display.

#include "vascsim/viewer/view_command.hpp"

#include "vascsim/viewer/viewer_app.hpp"

namespace vascsim::viewer {

namespace {

/// Returns the --max-fps option (its default depends on --measure).
CLI::Option* add_options(CLI::App& cmd, ViewOptions& o) {
  cmd.add_option("scene", o.scene, "Scene file (JSON)")->required();
  cmd.add_option("--set", o.sets,
                 "Override a scene key, e.g. --set geometry.node_spacing_m=0.5e-3 (repeatable)");
  cmd.add_option("--screenshot", o.screenshot, "Render headless (EGL) and write the last frame as a PNG");
  cmd.add_option("--fluoro-screenshot", o.fluoro_screenshot,
                 "With --screenshot: also write the last frame as fluoroscopy (C-arm at --lao, --cranial)");
  cmd.add_option("--frames", o.frames, "Frames to render (headless: default 1; window: until closed)")
      ->check(CLI::Range(0, 1000000));
  cmd.add_option("--size", o.size, "Window or picture size WIDTHxHEIGHT (default 1280x800)");
  cmd.add_flag("--headless", o.headless, "Render offscreen through EGL even when a display exists");
  cmd.add_flag("--realtime", o.realtime, "Headless: run the simulation and haptic threads as a window does");
  cmd.add_flag("--measure", o.measure, "glFinish between phases; print the frame-time split at the end");
  CLI::Option* max_fps = cmd.add_option("--max-fps", o.max_fps,
                                        "Visual frames per second at most (default 60; --measure: unlimited)")
                             ->check(CLI::Range(0.0, 1000.0));
  cmd.add_flag("--paused", o.paused, "Start paused (headless: draw the rest state)");
  cmd.add_flag("--play", o.play, "Drive the tool with the scene's scripted trajectory instead of the mouse");
  cmd.add_option("--replay", o.replay, "Drive the tool with a session recording (session.csv)");
  cmd.add_flag("--hud", o.hud, "Headless: draw the panel into the picture");
  cmd.add_option("--mode", o.mode, "lit or fluoro");
  cmd.add_option("--lao", o.lao_deg, "Fluoroscopy: C-arm LAO (+) / RAO (-), degrees");
  cmd.add_option("--cranial", o.cranial_deg, "Fluoroscopy: C-arm cranial (+) / caudal (-), degrees");
  cmd.add_option(
         "--fluoro-window", o.fluoro_window,
         "Fluoroscopy: scale on the attenuation (the monitor's window; 1: physical; default: the lumen's "
         "contrast path about 1)")
      ->check(CLI::Range(0.0, 1000.0));
  cmd.add_option("--yaw", o.yaw_deg, "Lit view: camera yaw about the superior axis, degrees");
  cmd.add_option("--pitch", o.pitch_deg, "Lit view: camera pitch, degrees (default 15)");
  cmd.add_option("--zoom", o.zoom, "Zoom notches (positive: closer)");
  cmd.add_flag("--cutaway", o.cutaway, "Cut away the near half of the wall");
  cmd.add_flag("--colour-map", o.colour_map, "Colour the wall by displacement");
  cmd.add_flag("--stress-map", o.stress_map, "Colour the wall by the von Mises stress");
  cmd.add_flag("--nodes", o.nodes, "Show the node cloud");
  cmd.add_flag("--tets", o.tets, "Show the virtual tetrahedra");
  cmd.add_flag("--no-contrast", o.no_contrast, "Fluoroscopy without contrast in the lumen");
  cmd.add_flag("--no-surface", o.no_surface, "Do not draw the wall (to check that a picture test notices)");
  cmd.add_option("--msaa", o.msaa, "Multisampling: 0, 2, 4 or 8");
  return max_fps;
}

}  // namespace

void add_view_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto opt = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand("view",
                                     "Show a scene live: the model driven with the mouse (or a recording) "
                                     "through the haptic loop, lit or fluoroscopic; or a headless picture");
  CLI::Option* max_fps = add_options(*cmd, *opt);
  commands.push_back({cmd, [opt, max_fps, &ctx] {
                        if (opt->measure && max_fps->count() == 0) opt->max_fps = 0.0;
                        return run_viewer(*opt, ctx.out);
                      }});
}

}  // namespace vascsim::viewer
