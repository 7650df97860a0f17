#pragma once
// The pictures of `vascsim navigate SCENE --pictures`: the vessel's wall at rest (the render surface the
// scene's geometry builds, as `vascsim view` draws it) with the instrument's last shape as a tube, rendered
// headless (EGL) twice: lit, with the near half of the wall cut away so the wire inside shows, and as an
// AP fluoroscopy. The navigation lives in the core library, which links no GL: the viewer library installs
// write_navigation_pictures in the CLI's context (install_navigation_pictures, apps/vascsim/main.cpp).

#include <filesystem>
#include <ostream>
#include <vector>

#include "vascsim/app/command.hpp"
#include "vascsim/render/renderer.hpp"
#include "vascsim/run/navigation.hpp"

namespace vascsim::viewer {

/// The picture's content: the wall of the scene's geometry at rest and the rod's final nodes as one
/// instrument of the scene's outer diameter.
render::RenderFrame navigation_frame(const Scene& scene, const NavigationResult& result);

/// The fluoroscopy of a navigation: the lumen holds blood, not contrast (a wire is advanced between
/// injections), and the attenuation is scaled so the instrument's diameter transmits about a fifth: the
/// wire stands out dark against the faint soft-tissue shadow of the vessel.
render::FluoroSettings navigation_fluoroscopy(double instrument_diameter_m);

/// Writes navigation_lit.png and navigation_fluoroscopy.png (1280 x 800) into `out_dir` and names them on
/// `out`. Throws RenderSetupError (an InputError: one line, exit code 2) when no headless OpenGL context can
/// be made.
void write_navigation_pictures(const Scene& scene, const NavigationResult& result,
                               const std::filesystem::path& out_dir, std::ostream& out);

/// A CommandAdder (cli.hpp) that adds no command: it gives `navigate --pictures` its writer.
void install_navigation_pictures(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);

}  // namespace vascsim::viewer
