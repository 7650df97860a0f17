#pragma once
// Scenes shared by several test files.

#include <nlohmann/json.hpp>

namespace vascsim::test {

/// 125 nodes: a 1 mm box (node spacing 0.25 mm), base fixed, the top pushed down `push_m` in `load_steps`
/// quasi-static load steps (relative tolerance 1e-6).
inline nlohmann::json tiny_box(double push_m = 1e-5, int load_steps = 2) {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "name": "tiny-box",
    "model": "quasi_static",
    "geometry": { "type": "box", "min_m": [0, 0, 0], "max_m": [1e-3, 1e-3, 1e-3], "node_spacing_m": 2.5e-4 },
    "material": { "youngs_modulus_pa": 5e5, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "regions": [
      { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } },
      { "name": "top", "select": { "type": "box", "min_m": [-1, -1, 1e-3] },
        "bc": { "type": "displacement", "direction": [0, 0, -1] } }
    ]
  })");
  scene["regions"][1]["bc"]["magnitude_m"] = push_m;
  scene["quasi_static"] = {{"load_steps", load_steps}, {"rel_tolerance", 1e-6}};
  return scene;
}

/// A 6 x 6 x 3 mm block (node spacing 0.5 mm: half the catheter's radius, docs/haptics.md), base fixed, under a
/// 6 Fr catheter lying across its top along x, tilted so that a press is deeper at x = 6 mm than at x = 0 and the
/// moment is not trivially zero; motion_m presses it 1 mm (0.9 mm at x = 6 mm, 0.42 mm at x = 0). The caller adds
/// the model and its settings block.
inline nlohmann::json catheter_pressed_block() {
  return nlohmann::json::parse(R"({
    "name": "catheter-block",
    "geometry": { "type": "box", "min_m": [0, 0, 0], "max_m": [0.006, 0.006, 0.003], "node_spacing_m": 0.0005 },
    "material": { "youngs_modulus_pa": 3e5, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } } ],
    "obstacles": [ { "name": "catheter", "shape": "catheter", "diameter_fr": 6, "length_m": 0.01,
                     "tip_m": [0.0075, 0.0032, 0.00398], "direction": [1, 0, -0.08], "motion_m": [0, 0, -0.001] } ]
  })");
}

}  // namespace vascsim::test
