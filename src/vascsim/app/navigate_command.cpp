// `vascsim navigate SCENE`: the scene's flexible instrument advanced through the vessel's lumen by its drive
// (run/navigation.hpp), with instrument.csv (a row per frame), instrument_final.csv (the rod's last shape)
// and summary.json in the output folder; with --pictures also navigation_lit.png and
// navigation_fluoroscopy.png (drawn by the viewer library: CliContext::navigation_pictures).

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "vascsim/app/command.hpp"
#include "vascsim/app/progress.hpp"
#include "vascsim/core/atomic_file.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/run/navigation.hpp"

namespace vascsim {

namespace {

struct NavigateFlags {
  std::string scene, out;
  std::vector<std::string> sets;
  bool pictures = false;
};

nlohmann::json summary(const Scene& scene, const NavigationResult& r) {
  double force_max = 0.0, torque_max = 0.0, wall_max = 0.0, outside_max = -1.0, ms_total = 0.0;
  std::vector<double> ms;
  for (const NavigationFrame& f : r.frames) {
    force_max = std::max(force_max, std::abs(f.insertion_force_n));
    torque_max = std::max(torque_max, std::abs(f.torque_n_m));
    wall_max = std::max(wall_max, f.wall_force_max_n);
    outside_max = std::max(outside_max, f.outside_max_m);
    ms.push_back(f.wall_ms);
    ms_total += f.wall_ms;
  }
  std::sort(ms.begin(), ms.end());
  const NavigationFrame& last = r.frames.back();
  const rod::InstrumentSpec& s = *scene.instrument;
  return {{"scene", scene.name},
          {"scene_file", scene.file},
          {"wall", "rigid"},
          {"lumen_radius_m", r.lumen_radius_m},
          {"instrument",
           {{"name", s.name},
            {"preset", s.preset},
            {"outer_diameter_m", s.section.outer_diameter_m},
            {"inner_diameter_m", s.section.inner_diameter_m},
            {"youngs_modulus_pa", s.section.youngs_modulus_pa},
            {"shear_modulus_pa", s.section.shear_modulus_pa},
            {"length_m", s.length_m},
            {"edge_length_m", s.edge_length_m},
            {"friction", s.friction}}},
          {"frames", r.frames.size()},
          {"unconverged_frames", r.unconverged},
          {"perforation_frames", r.perforation_frames},
          {"final",
           {{"time_s", last.time_s},
            {"inserted_m", last.inserted_m},
            {"twist_rad", last.twist_rad},
            {"tip_s_m", last.tip_s_m},
            {"insertion_force_n", last.insertion_force_n},
            {"torque_n_m", last.torque_n_m}}},
          {"insertion_force_max_n", force_max},
          {"torque_max_n_m", torque_max},
          {"wall_force_max_n", wall_max},
          {"outside_max_m", outside_max},
          {"frame_wall_ms_median", ms[ms.size() / 2]},
          {"solve_wall_s", ms_total * 1e-3}};
}

int navigate(NavigateFlags& flags, CliContext& ctx) {
  // Before the run, which may take minutes: a build without GL cannot draw its end.
  if (flags.pictures && ctx.navigation_pictures == nullptr)
    throw InputError(
        "--pictures: this vascsim was built without the viewer: configure with -DVASCSIM_BUILD_VIEWER=ON "
        "(the GL packages are in scripts/install-deps.sh)");
  const Scene scene = load_scene(flags.scene, flags.sets);
  if (!scene.instrument)
    throw InputError(
        fmt::format("{}: the scene has no 'instrument' block; add one (docs/scene-format.md, "
                    "\"instrument\")",
                    scene.file));
  NavigationOptions options;
  options.out_dir =
      flags.out.empty() ? std::filesystem::path("out") / scene.name : std::filesystem::path(flags.out);
  spdlog::info("navigate '{}' ({}): '{}' in the rigid lumen, output {}", scene.name, scene.file,
               scene.instrument->name, options.out_dir.string());
  Progress progress(ctx.err, ctx.err_is_terminal(), scene.name, ctx.quiet);
  options.on_progress = [&](int done, int total) {
    progress.update(done, std::max(total, 1), fmt::format("frame {} of {}", done, total));
  };
  const NavigationResult r = run_navigation(scene, options);
  progress.finish();
  const nlohmann::json s = summary(scene, r);
  write_file_atomically(options.out_dir / "summary.json", s.dump(2) + "\n");
  const NavigationFrame& last = r.frames.back();
  ctx.out << fmt::format(
      "{}: '{}' {:.1f} mm in, turned {:.0f} deg, tip at {:.1f} mm along the centre-line; insertion force "
      "{:.3g} N "
      "(largest {:.3g} N), torque {:.3g} N m, largest wall force {:.3g} N, never beyond the wall by more "
      "than {:.3g} "
      "mm; {} frames, median {:.1f} ms; wrote {}\n",
      scene.name, scene.instrument->name, last.inserted_m * 1e3, last.twist_rad * 180.0 / std::numbers::pi,
      last.tip_s_m * 1e3, last.insertion_force_n, s["insertion_force_max_n"].get<double>(), last.torque_n_m,
      s["wall_force_max_n"].get<double>(), std::max(0.0, s["outside_max_m"].get<double>()) * 1e3,
      r.frames.size(), s["frame_wall_ms_median"].get<double>(),
      (options.out_dir / "instrument.csv").string());
  if (flags.pictures) ctx.navigation_pictures(scene, r, options.out_dir, ctx.out);
  if (r.perforation_frames > 0)
    spdlog::warn(
        "{}: in {} frames a wall force exceeded the perforation threshold instrument.perforation_force_n "
        "({} N): instrument.csv, column perforation_risk",
        scene.name, r.perforation_frames, scene.instrument->perforation_force_n);
  if (r.unconverged > 0) {
    ctx.err << fmt::format(
        "NOT CONVERGED: {} of {} frames did not reach equilibrium (instrument.csv, column "
        "converged)\n",
        r.unconverged, r.frames.size());
    return kExitUnconverged;
  }
  return 0;
}

}  // namespace

void add_navigate_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands) {
  auto flags = std::make_shared<NavigateFlags>();
  CLI::App* cmd = app.add_subcommand(
      "navigate",
      "Advance the scene's flexible instrument (guidewire, catheter) through the vessel's lumen by its drive "
      "(the wall rigid; docs/model/26-rod.md)");
  cmd->add_option("scene", flags->scene, "Scene JSON with an 'instrument' block and a vessel geometry")
      ->required();
  cmd->add_option("--set", flags->sets, "Override a scene key: path.to.key=value (repeatable)");
  cmd->add_option("--out", flags->out, "Output folder (default: out/<scene name>)");
  cmd->add_flag("--pictures", flags->pictures,
                "After the run, draw the vessel with the instrument's last shape: navigation_lit.png (the "
                "wall cut open) and navigation_fluoroscopy.png (an AP X-ray) in the output folder; headless "
                "OpenGL (EGL), builds with the viewer");
  commands.push_back({cmd, [flags, &ctx] { return navigate(*flags, ctx); }});
}

}  // namespace vascsim
