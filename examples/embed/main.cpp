// Embedding vascsim: load a scene, advance it through its output points, read the node positions and the
// force on the tool. Usage: embed SCENE.json [path.to.key=value ...] (the overrides of `vascsim run --set`).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "vascsim/core/error.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: embed SCENE.json [path.to.key=value ...]\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::warn);  // the library logs its progress through spdlog's default logger
  try {
    const vascsim::Scene scene =
        vascsim::load_scene(argv[1], std::vector<std::string>(argv + 2, argv + argc));
    vascsim::Simulation sim(scene);  // geometry, discretisation, energy, the scene's model
    const vascsim::Vec3Array& rest = sim.discretization().rest_positions();
    for (int k = 1; k <= sim.model().num_steps(); ++k) {
      const vascsim::StepRecord record = sim.advance(k);
      const vascsim::Vec3Array& x = sim.model().positions();  // m
      double max_displacement_m = 0.0;
      for (std::size_t i = 0; i < x.size(); ++i)
        max_displacement_m = std::max(max_displacement_m, (x[i] - rest[i]).norm());
      std::printf("step %d: load factor %.3f, max displacement %.6g m", k, record.report.load_factor,
                  max_displacement_m);
      if (!record.obstacles.empty()) {
        const vascsim::Vec3 on_tool =
            -record.obstacles[0].force_vector_n;  // the tissue's force on the first tool, N
        std::printf(", force on tool '%s' %.9g %.9g %.9g N", scene.obstacles[0].name.c_str(), on_tool.x(),
                    on_tool.y(), on_tool.z());
      }
      std::printf("\n");
    }
  } catch (const vascsim::InputError& e) {  // bad scene, key or value: the message names the file and key
    std::fprintf(stderr, "embed: error: %s\n", e.what());
    return 2;
  } catch (const vascsim::NumericalError& e) {
    std::fprintf(stderr, "embed: numerical error: %s\n", e.what());
    return 3;
  }
  return 0;
}
