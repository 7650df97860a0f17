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

/// A 6 x 6 x 3 mm block (node spacing 0.5 mm: half the catheter's radius, docs/haptics.md), base fixed, under
/// a 6 Fr catheter lying across its top along x, tilted so that a press is deeper at x = 6 mm than at x = 0
/// and the moment is not trivially zero; motion_m presses it 1 mm (0.9 mm at x = 6 mm, 0.42 mm at x = 0). The
/// caller adds the model and its settings block.
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

/// A 6 mm piece of the hand dorsal vein at the real-time resolution (outer radius 1.5 mm, wall 0.3 mm, node
/// spacing 0.3 mm along the wall, three layers through it: 1,764 nodes on a wall lattice), both ends clamped,
/// the 6 Fr catheter 0.2 mm above the outer wall at mid-length pointing into it; motion_m presses it 0.6 mm.
/// Model `implicit` with the given settings block.
inline nlohmann::json vein_piece_catheter(const nlohmann::json& implicit_settings) {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "name": "vein-piece-catheter",
    "model": "implicit",
    "geometry": { "type": "vessel", "centerline": { "type": "straight", "length_m": 6e-3 },
                  "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "node_spacing_m": 0.3e-3, "min_layers": 3 },
    "material": { "youngs_modulus_pa": 0.5e6, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "max_growths": 10 },
    "regions": [
      { "name": "end_start", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } },
      { "name": "end_finish", "select": { "type": "cylinder_end", "end": "end" }, "bc": { "type": "fixed" } }
    ],
    "obstacles": [ { "name": "catheter", "shape": "catheter", "diameter_fr": 6, "length_m": 5e-3,
                     "tip_m": [0, 1.7e-3, 3e-3], "direction": [0, -1, 0], "motion_m": [0, -0.8e-3, 0] } ]
  })");
  scene["implicit"] = implicit_settings;
  return scene;
}

}  // namespace vascsim::test
