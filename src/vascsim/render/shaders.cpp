#include "vascsim/render/shaders.hpp"

#include "vascsim/render/colour_map.hpp"

namespace vascsim::render::shaders {

namespace {

// Integer hash and value noise shared by the wall texture and the fluoroscopy grain. The noise lattice
// wraps with a given period in x and y, so a pattern on a tile is seamless when the tile repeats.
const char* kNoise = R"(
uint mix_bits(uint h) {
  h ^= h >> 16; h *= 0x7feb352du;
  h ^= h >> 15; h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}
float cell_value(ivec2 c, ivec2 period) {
  ivec2 w = ((c % period) + period) % period;
  uint h = mix_bits(uint(w.x) * 0x9e3779b1u + mix_bits(uint(w.y) + 0x632be5abu));
  return float(h >> 8) * (1.0 / 16777216.0);
}
float value_noise(vec2 p, ivec2 period) {
  ivec2 i = ivec2(floor(p));
  vec2 f = p - floor(p);
  vec2 w = f * f * (3.0 - 2.0 * f);
  float a = cell_value(i, period), b = cell_value(i + ivec2(1, 0), period);
  float c = cell_value(i + ivec2(0, 1), period), d = cell_value(i + ivec2(1, 1), period);
  return mix(mix(a, b, w.x), mix(c, d, w.x), w.y);
}
// Sum of `octaves` noises, each twice the frequency and half the amplitude; in [0, 1].
float layered_noise(vec2 p, ivec2 period, int octaves) {
  float sum = 0.0, amp = 0.5, norm = 0.0;
  for (int k = 0; k < octaves; ++k) {
    sum += amp * value_noise(p, period);
    norm += amp;
    p *= 2.0;
    period *= 2;
    amp *= 0.5;
  }
  return sum / norm;
}
)";

}  // namespace

std::string surface_vertex() {
  return R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in float a_outer;
layout(location = 4) in float a_scalar;
uniform mat4 u_view_proj;
uniform vec4 u_clip_plane;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_param;  // u, cos(2 pi v), sin(2 pi v): v is recovered per fragment, so the seam needs no split
out float v_outer;
out float v_scalar;
void main() {
  float angle = 6.28318530718 * a_uv.y;
  v_world = a_position;
  v_normal = a_normal;
  v_param = vec3(a_uv.x, cos(angle), sin(angle));
  v_outer = a_outer;
  v_scalar = a_scalar;
  gl_ClipDistance[0] = dot(vec4(a_position, 1.0), u_clip_plane);
  gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";
}

std::string surface_fragment() {
  return std::string(R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec3 v_param;
in float v_outer;
in float v_scalar;
uniform vec3 u_eye;
uniform vec3 u_key_light;   // unit vector towards the key light
uniform vec3 u_fill_light;  // unit vector towards the fill light
uniform float u_uv_aspect;  // vessel length / circumference
uniform int u_colour_mode;  // 0: wall texture, 1: colour map
uniform bool u_baked;       // the texture is the baked procedural wall (alpha: intima detail)
uniform vec2 u_scalar_range;
uniform sampler2D u_texture;
uniform float u_texture_cells;  // texture tiles around the vessel
out vec4 o_colour;
)") + colour_map_glsl() +
         R"(
const float kTwoPi = 6.28318530718;

vec3 to_linear(vec3 c) { return c * c; }  // gamma 2: close to sRGB, and cheap

void main() {
  // v from the interpolated (cos, sin) pair, and its screen derivatives without the seam's jump.
  vec2 cs = v_param.yz;
  float v = fract(atan(cs.y, cs.x) / kTwoPi + 1.0);
  float r2 = max(dot(cs, cs), 1e-6);
  vec2 dv = vec2(cs.x * dFdx(cs.y) - cs.y * dFdx(cs.x), cs.x * dFdy(cs.y) - cs.y * dFdy(cs.x)) / (kTwoPi * r2);
  vec2 du = vec2(dFdx(v_param.x), dFdy(v_param.x));

  bool outer_wall = v_outer > 0.5;
  vec3 albedo;
  if (u_colour_mode == 1) {
    float t = (v_scalar - u_scalar_range.x) / max(u_scalar_range.y - u_scalar_range.x, 1e-30);
    albedo = colour_map(t);
  } else {
    // One tile is one circumference square: u * aspect along, v around.
    vec2 tc = vec2(v_param.x * u_uv_aspect, v) * u_texture_cells;
    vec4 texel = textureGrad(u_texture, tc, vec2(du.x * u_uv_aspect, dv.x) * u_texture_cells,
                             vec2(du.y * u_uv_aspect, dv.y) * u_texture_cells);
    if (outer_wall)
      albedo = texel.rgb;
    else if (u_baked)
      albedo = vec3(0.52, 0.47, 0.66) * (0.9 + 0.16 * texel.a);  // the intima: smooth, paler, bluish
    else
      albedo = texel.rgb * vec3(0.70, 0.72, 0.95);
  }
  vec3 base = to_linear(albedo);
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) {
    // Seen from behind: the cut face of the wall (cutaway) or the far side of the inner wall.
    n = -n;
    base *= vec3(0.45, 0.42, 0.55);
  }
  vec3 view = normalize(u_eye - v_world);
  float key = max(dot(n, u_key_light), 0.0);
  float fill = max(dot(n, u_fill_light), 0.0);
  vec3 h = normalize(u_key_light + view);
  float shininess = outer_wall ? 40.0 : 90.0;
  float spec = pow(max(dot(n, h), 0.0), shininess) * (outer_wall ? 0.22 : 0.45) * step(0.0, dot(n, u_key_light));
  vec3 lit = base * (0.16 + 0.80 * key + 0.25 * fill) + vec3(spec);
  o_colour = vec4(sqrt(lit), 1.0);
}
)";
}

// The procedural wall, baked once into a tile (one circumference square, kCells x kCells noise cells,
// periodic both ways) that the surface shader samples with mipmaps: cheap per fragment, and filtered.
// rgb: the outer wall (adventitia, sRGB); a: fine detail for the intima.
std::string wall_bake_fragment() {
  return std::string(R"(#version 330 core
in vec2 v_uv;
out vec4 o_colour;
)") + kNoise +
         R"(
const float kTwoPi = 6.28318530718;
const int kCells = 10;  // noise cells across the tile (even: the warp uses half)

// Thin meandering lines where a noise field crosses one half: the vasa vasorum. The distance to the
// crossing, in texels, is |n - 0.5| over the gradient, so a line keeps its width where the field is flat.
// The periods must be the extent of q across the tile in cells; q * 0.5 wraps with period / 2.
float streaks(vec2 q, ivec2 period, float half_width_texels) {
  vec2 warp = vec2(layered_noise(q * 0.5 + vec2(3.1, 0.0), period / 2, 3),
                   layered_noise(q * 0.5 + vec2(17.3, 0.0), period / 2, 3));
  float n = layered_noise(q + 1.6 * warp, period, 4);
  float distance = abs(n - 0.5) / max(length(vec2(dFdx(n), dFdy(n))), 1e-6);
  return 1.0 - smoothstep(0.3 * half_width_texels, half_width_texels, distance);
}

void main() {
  vec2 q = v_uv * float(kCells);
  ivec2 cells = ivec2(kCells);
  float blotch = layered_noise(q * 0.5, cells / 2, 3);
  float fine = layered_noise(q * 8.0, cells * 8, 2);
  // A faint helical fibre texture of the media/adventitia.
  float fibres = 0.5 + 0.5 * sin(kTwoPi * (q.y * 14.0 + q.x * 3.0) + 4.0 * fine);
  vec3 tissue = mix(vec3(0.80, 0.40, 0.38), vec3(0.88, 0.66, 0.50), 0.45 * smoothstep(0.45, 0.8, blotch));
  tissue *= (0.92 + 0.16 * fine) * (1.0 - 0.07 * fibres);
  // Vessels of the vessel wall: long lines mostly along the axis (x stretched by 0.4), finer branches.
  float vv = max(streaks(vec2(q.x * 0.4, q.y), ivec2(kCells * 2 / 5, kCells), 3.0),
                 0.6 * streaks(q * 2.0 + vec2(11.0, 0.0), cells * 2, 1.6));
  vec3 outer = mix(tissue, vec3(0.50, 0.06, 0.09), 0.85 * vv);
  o_colour = vec4(outer, clamp(fine * (1.0 - 0.3 * fibres), 0.0, 1.0));
}
)";
}

std::string solid_vertex() {
  return R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() {
  v_world = a_position;
  v_normal = a_normal;
  gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";
}

std::string solid_fragment() {
  return R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
uniform vec3 u_eye;
uniform vec3 u_key_light;
uniform vec3 u_fill_light;
uniform vec3 u_colour;  // sRGB
uniform float u_shininess;
out vec4 o_colour;
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 view = normalize(u_eye - v_world);
  vec3 h = normalize(u_key_light + view);
  vec3 base = pow(u_colour, vec3(2.2));
  float key = max(dot(n, u_key_light), 0.0);
  float fill = max(dot(n, u_fill_light), 0.0);
  float spec = 0.6 * pow(max(dot(n, h), 0.0), u_shininess) * step(0.0, dot(n, u_key_light));
  // A thin dark rim keeps the tool readable against a pale wall.
  float rim = 1.0 - 0.35 * pow(1.0 - max(dot(n, view), 0.0), 3.0);
  vec3 lit = (base * (0.18 + 0.78 * key + 0.22 * fill) + vec3(spec)) * rim;
  o_colour = vec4(pow(lit, vec3(1.0 / 2.2)), 1.0);
}
)";
}

std::string overlay_vertex() {
  return R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
uniform float u_point_size;
void main() {
  gl_PointSize = u_point_size;
  gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";
}

std::string overlay_fragment() {
  return R"(#version 330 core
uniform vec4 u_colour;
out vec4 o_colour;
void main() { o_colour = u_colour; }
)";
}

std::string fluoro_accumulate_vertex() {
  return R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
uniform vec3 u_source;  // the X-ray source (the centre of projection), world
out vec3 v_ray;
void main() {
  v_ray = a_position - u_source;
  gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";
}

// Along every ray through a closed, consistently oriented surface, entering crossings face the source
// and leaving ones face away, so the sum of (leaving ? +distance : -distance) over its fragments is the
// length of the ray inside the solid. Weighted by the attenuation coefficient (1/m) it is that solid's
// share of the line integral mu * length; the sign of u_weight flips surfaces oriented inwards.
std::string fluoro_accumulate_fragment() {
  return R"(#version 330 core
in vec3 v_ray;
uniform float u_weight;
uniform bool u_front_is_entry;
out float o_attenuation;
void main() {
  float d = length(v_ray);
  bool entering = gl_FrontFacing == u_front_is_entry;
  o_attenuation = u_weight * (entering ? -d : d);
}
)";
}

std::string fullscreen_vertex() {
  return R"(#version 330 core
out vec2 v_uv;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  v_uv = p;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";
}

std::string fluoro_composite_fragment() {
  return R"(#version 330 core
in vec2 v_uv;
uniform sampler2D u_attenuation;
uniform sampler2D u_grain;   // 256 x 256 uniform noise in [0, 1], wrapped
uniform ivec2 u_grain_offset;  // changes every frame
uniform float u_background;  // grey level with nothing in the beam
uniform float u_floor;       // grey level behind an opaque object (scatter, display black level)
uniform float u_vignette;    // darkening towards the corners
uniform float u_noise;       // quantum mottle amplitude
out vec4 o_colour;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  float a = max(texelFetch(u_attenuation, px, 0).r, 0.0);
  float transmitted = exp(-a);
  vec2 c = v_uv - 0.5;
  float field = u_background * (1.0 - u_vignette * dot(c, c) * 2.0);
  float grey = u_floor + (field - u_floor) * transmitted;
  float grain = texelFetch(u_grain, (px + u_grain_offset) & 255, 0).r - 0.5;
  grey += u_noise * grain * sqrt(max(grey, 0.0));
  o_colour = vec4(vec3(clamp(grey, 0.0, 1.0)), 1.0);
}
)";
}

}  // namespace vascsim::render::shaders
