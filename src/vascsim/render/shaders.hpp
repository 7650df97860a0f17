#pragma once
// GLSL 3.30 core sources of the renderer's programs (written for vascsim).
//  - surface: the vessel wall, Blinn-Phong with the wall texture on (u, v) or the colour map;
//  - wall_bake: the procedural wall texture, rendered once into a periodic tile;
//  - solid: tools and the force arrow, Blinn-Phong with one colour;
//  - overlay: node points and tetrahedron edges, one colour;
//  - fluoro_accumulate: signed path length through closed surfaces into a float target;
//  - fluoro_composite: the accumulated attenuation to a grey X-ray picture.

#include <string>

namespace vascsim::render::shaders {

std::string surface_vertex();
std::string surface_fragment();
std::string wall_bake_fragment();  ///< with fullscreen_vertex()
std::string solid_vertex();
std::string solid_fragment();
std::string overlay_vertex();
std::string overlay_fragment();
std::string fluoro_accumulate_vertex();
std::string fluoro_accumulate_fragment();
std::string fullscreen_vertex();
std::string fluoro_composite_fragment();

}  // namespace vascsim::render::shaders
