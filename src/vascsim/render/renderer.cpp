#include "vascsim/render/renderer.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "vascsim/render/gl_program.hpp"
#include "vascsim/render/lumen_caps.hpp"
#include "vascsim/render/shaders.hpp"
#include "vascsim/render/tool_geometry.hpp"
#include "vascsim/render/wall_texture.hpp"

namespace vascsim::render {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

template <typename T>
std::size_t bytes_of(const std::vector<T>& v) {
  return v.size() * sizeof(T);
}

// Replaces the whole buffer store (orphaning it): the driver need not wait for draws still reading the
// previous contents.
template <typename T>
std::size_t stream(GLenum target, GLuint buffer, const std::vector<T>& data) {
  glBindBuffer(target, buffer);
  glBufferData(target, static_cast<GLsizeiptr>(bytes_of(data)), data.empty() ? nullptr : data.data(),
               GL_STREAM_DRAW);
  return bytes_of(data);
}

Eigen::Matrix4f to_float(const Eigen::Matrix4d& m) {
  return m.cast<float>();
}
Float3 to_float(const Vec3& v) {
  return v.cast<float>();
}

}  // namespace

struct Renderer::Impl {
  GlProgram surface, solid, overlay, accumulate, composite;
  GLuint baked_texture = 0;  // the procedural wall, baked once
  GLuint grain_texture = 0;  // fluoroscopy quantum mottle: a tile of uniform noise

  // Wall surface: one VAO for the lit pass (all attributes), one for the fluoroscopy pass (positions and
  // its own index buffer: the triangles with an outer vertex, then the inner wall, then the lumen caps).
  GLuint surface_vao = 0, lumen_vao = 0;
  GLuint position_vbo = 0, normal_vbo = 0, uv_vbo = 0, outer_vbo = 0, scalar_vbo = 0;
  GLuint triangle_ebo = 0, lumen_ebo = 0;
  std::size_t vertices = 0, triangles = 0;
  std::size_t fluoro_wall = 0, fluoro_inner = 0, fluoro_caps = 0;  // triangles in the three ranges
  std::uint64_t topology_version = ~std::uint64_t{0};
  bool has_uv = false, has_outer = false, has_scalar = false;
  float uv_aspect = 1.0f;
  ScalarField scalar_info;  // range and label (values go to the GPU)
  std::vector<Float3> normals_scratch;

  // Tools (capsules), flexible instruments (tubes) and the force arrow: rebuilt every upload.
  GLuint solid_vao = 0, solid_position_vbo = 0, solid_normal_vbo = 0, solid_ebo = 0;
  SolidMesh solid_mesh;
  struct ToolDraw {
    std::size_t first = 0, count = 0;  // triangles
    Float3 colour;
  };
  std::vector<ToolDraw> tool_draws;
  std::size_t tool_triangles = 0;  // tools and instruments first, then the arrow
  std::size_t arrow_first = 0, arrow_count = 0;
  Float3 arrow_colour = Float3::Zero();

  // Overlays.
  GLuint node_vao = 0, node_vbo = 0, tet_ebo = 0;
  std::size_t nodes = 0, tet_edges = 0;

  // Fluoroscopy accumulation target.
  GLuint accum_fbo = 0, accum_texture = 0;
  int accum_w = 0, accum_h = 0;
  GLuint empty_vao = 0;

  GLuint wall_texture = 0;
  float texture_repeats = 1.0f;
  Bounds bounds;

  Impl()
      : surface("surface", shaders::surface_vertex(), shaders::surface_fragment()),
        solid("solid", shaders::solid_vertex(), shaders::solid_fragment()),
        overlay("overlay", shaders::overlay_vertex(), shaders::overlay_fragment()),
        accumulate("fluoro_accumulate", shaders::fluoro_accumulate_vertex(),
                   shaders::fluoro_accumulate_fragment()),
        composite("fluoro_composite", shaders::fullscreen_vertex(), shaders::fluoro_composite_fragment()) {
    bake_wall_texture();
    make_grain_texture();
    GLuint b[12];
    glGenBuffers(12, b);
    position_vbo = b[0], normal_vbo = b[1], uv_vbo = b[2], outer_vbo = b[3], scalar_vbo = b[4];
    triangle_ebo = b[5], lumen_ebo = b[6], solid_position_vbo = b[7], solid_normal_vbo = b[8],
    solid_ebo = b[9];
    node_vbo = b[10], tet_ebo = b[11];
    GLuint v[5];
    glGenVertexArrays(5, v);
    surface_vao = v[0], lumen_vao = v[1], solid_vao = v[2], node_vao = v[3], empty_vao = v[4];

    glBindVertexArray(surface_vao);
    attribute(0, position_vbo, 3, GL_FLOAT, GL_FALSE);
    attribute(1, normal_vbo, 3, GL_FLOAT, GL_FALSE);
    attribute(2, uv_vbo, 2, GL_FLOAT, GL_FALSE);
    attribute(3, outer_vbo, 1, GL_UNSIGNED_BYTE, GL_FALSE);  // 0 or 1 as float
    attribute(4, scalar_vbo, 1, GL_FLOAT, GL_FALSE);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, triangle_ebo);

    glBindVertexArray(lumen_vao);
    attribute(0, position_vbo, 3, GL_FLOAT, GL_FALSE);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, lumen_ebo);

    glBindVertexArray(solid_vao);
    attribute(0, solid_position_vbo, 3, GL_FLOAT, GL_FALSE);
    attribute(1, solid_normal_vbo, 3, GL_FLOAT, GL_FALSE);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, solid_ebo);

    glBindVertexArray(node_vao);
    attribute(0, node_vbo, 3, GL_FLOAT, GL_FALSE);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, tet_ebo);
    glBindVertexArray(0);
  }

  ~Impl() {
    const GLuint b[12] = {position_vbo,     normal_vbo,   uv_vbo,    outer_vbo,
                          scalar_vbo,       triangle_ebo, lumen_ebo, solid_position_vbo,
                          solid_normal_vbo, solid_ebo,    node_vbo,  tet_ebo};
    glDeleteBuffers(12, b);
    const GLuint v[5] = {surface_vao, lumen_vao, solid_vao, node_vao, empty_vao};
    glDeleteVertexArrays(5, v);
    if (accum_fbo != 0) glDeleteFramebuffers(1, &accum_fbo);
    if (accum_texture != 0) glDeleteTextures(1, &accum_texture);
    if (wall_texture != 0) glDeleteTextures(1, &wall_texture);
    glDeleteTextures(1, &baked_texture);
    glDeleteTextures(1, &grain_texture);
  }

  void make_grain_texture() {
    constexpr int kSize = 256;
    std::vector<float> values(kSize * kSize);
    std::mt19937 rng(20210327u);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float& v : values) v = uniform(rng);
    glGenTextures(1, &grain_texture);
    glBindTexture(GL_TEXTURE_2D, grain_texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, kSize, kSize, 0, GL_RED, GL_FLOAT, values.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
  }

  // Renders the procedural wall tile into a mipmapped, repeating texture.
  void bake_wall_texture() {
    constexpr int kSize = 1024;
    GlProgram bake("wall_bake", shaders::fullscreen_vertex(), shaders::wall_bake_fragment());
    glGenTextures(1, &baked_texture);
    glBindTexture(GL_TEXTURE_2D, baked_texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kSize, kSize, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    GLuint fbo = 0, vao = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, baked_texture, 0);
    glViewport(0, 0, kSize, kSize);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    bake.use();
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vao);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
  }

  static void attribute(GLuint index, GLuint vbo, int size, GLenum type, GLboolean normalized) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glVertexAttribPointer(index, size, type, normalized, 0, nullptr);
    glEnableVertexAttribArray(index);
  }

  // Enables a surface attribute array, or disables it (draw() then sets the constant the shader reads:
  // generic attribute values are context state, not VAO state).
  void use_array(GLuint index, bool present) {
    glBindVertexArray(surface_vao);
    if (present)
      glEnableVertexAttribArray(index);
    else
      glDisableVertexAttribArray(index);
  }

  void ensure_accumulation_target(int w, int h) {
    if (accum_fbo != 0 && accum_w == w && accum_h == h) return;
    if (accum_fbo == 0) {
      glGenFramebuffers(1, &accum_fbo);
      glGenTextures(1, &accum_texture);
    }
    glBindTexture(GL_TEXTURE_2D, accum_texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, w, h, 0, GL_RED, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, accum_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, accum_texture, 0);
    accum_w = w;
    accum_h = h;
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

std::size_t Renderer::triangle_count() const {
  return impl_->triangles;
}
std::size_t Renderer::vertex_count() const {
  return impl_->vertices;
}

void Renderer::set_wall_texture(const std::string& path, float repeats) {
  const GLuint texture = load_texture_file(path);
  clear_wall_texture();
  impl_->wall_texture = texture;
  impl_->texture_repeats = repeats > 0.0f ? repeats : 1.0f;
}

void Renderer::clear_wall_texture() {
  if (impl_->wall_texture != 0) glDeleteTextures(1, &impl_->wall_texture);
  impl_->wall_texture = 0;
}

CameraPose Renderer::pose_for(const OrbitCamera& camera, const RenderSettings& settings) {
  return settings.mode == ViewMode::fluoroscopy
             ? camera.carm_pose(settings.carm_lao_deg, settings.carm_cranial_deg)
             : camera.pose();
}

void Renderer::upload(const RenderFrame& frame, bool measure) {
  validate_frame(frame);
  Impl& m = *impl_;
  if (measure) glFinish();
  const auto t0 = Clock::now();
  std::size_t bytes = upload_per_frame_arrays(frame);
  bytes += upload_topology(frame);
  m.uv_aspect = frame.uv_aspect > 0.0f ? frame.uv_aspect : 1.0f;
  m.bounds = scene_bounds(frame);
  bytes += upload_tools_and_arrow(frame);
  bytes += upload_overlays(frame);
  if (measure) glFinish();
  timing_.upload_ms = ms_since(t0);
  timing_.uploaded_bytes = bytes;
}

// Every frame: positions, normals (computed when the frame has none), the scalar field.
std::size_t Renderer::upload_per_frame_arrays(const RenderFrame& frame) {
  Impl& m = *impl_;
  std::size_t bytes = 0;
  m.vertices = frame.positions_m.size();
  bytes += stream(GL_ARRAY_BUFFER, m.position_vbo, frame.positions_m);
  const std::vector<Float3>* normals = &frame.normals;
  if (frame.normals.empty()) {
    compute_normals(frame.positions_m, frame.triangles, m.normals_scratch);
    normals = &m.normals_scratch;
  }
  bytes += stream(GL_ARRAY_BUFFER, m.normal_vbo, *normals);
  m.has_scalar = frame.scalar.has_value();
  if (m.has_scalar) {
    bytes += stream(GL_ARRAY_BUFFER, m.scalar_vbo, frame.scalar->values);
    m.scalar_info.min = frame.scalar->min;
    m.scalar_info.max = frame.scalar->max;
  }
  m.use_array(4, m.has_scalar);
  return bytes;
}

// When the topology changed: triangles, uv, outer flags, and the fluoroscopy's lumen (inner wall and caps).
std::size_t Renderer::upload_topology(const RenderFrame& frame) {
  Impl& m = *impl_;
  std::size_t bytes = 0;
  if (frame.topology_version == m.topology_version && frame.triangles.size() == m.triangles) return 0;
  m.topology_version = frame.topology_version;
  m.triangles = frame.triangles.size();
  bytes += stream(GL_ELEMENT_ARRAY_BUFFER, m.triangle_ebo, frame.triangles);  // surface_vao is bound
  m.has_uv = !frame.uv.empty();
  if (m.has_uv) bytes += stream(GL_ARRAY_BUFFER, m.uv_vbo, frame.uv);
  m.use_array(2, m.has_uv);
  m.has_outer = !frame.outer.empty();
  if (m.has_outer) bytes += stream(GL_ARRAY_BUFFER, m.outer_vbo, frame.outer);
  m.use_array(3, m.has_outer);
  // The inner wall bounds both the wall solid and the lumen: drawn once with the difference of the two
  // weights instead of twice.
  const auto lumen = lumen_surface(frame.triangles, frame.outer);  // inner triangles, then the caps
  std::vector<std::array<std::uint32_t, 3>> fluoro;
  fluoro.reserve(frame.triangles.size() + lumen.size());
  for (const auto& t : frame.triangles)
    if (frame.outer.empty() || frame.outer[t[0]] != 0 || frame.outer[t[1]] != 0 || frame.outer[t[2]] != 0)
      fluoro.push_back(t);
  m.fluoro_wall = fluoro.size();
  m.fluoro_inner = frame.triangles.size() - m.fluoro_wall;
  m.fluoro_caps = lumen.size() - m.fluoro_inner;
  fluoro.insert(fluoro.end(), lumen.begin(), lumen.end());
  glBindVertexArray(m.lumen_vao);
  bytes += stream(GL_ELEMENT_ARRAY_BUFFER, m.lumen_ebo, fluoro);
  return bytes;
}

// The tools as capsules, the instruments as tubes (both drawn and X-rayed as tools) and the force arrow,
// coloured by the safety threshold.
std::size_t Renderer::upload_tools_and_arrow(const RenderFrame& frame) {
  Impl& m = *impl_;
  std::size_t bytes = 0;
  m.solid_mesh.clear();
  m.tool_draws.clear();
  for (const ToolCapsule& tool : frame.tools) {
    const std::size_t first = m.solid_mesh.triangles.size();
    append_capsule(m.solid_mesh, tool);
    m.tool_draws.push_back({first, m.solid_mesh.triangles.size() - first, tool.colour});
  }
  for (const InstrumentTube& tube : frame.instruments) {
    const std::size_t first = m.solid_mesh.triangles.size();
    append_tube(m.solid_mesh, tube);
    m.tool_draws.push_back({first, m.solid_mesh.triangles.size() - first, tube.colour});
  }
  m.tool_triangles = m.solid_mesh.triangles.size();
  m.arrow_first = m.tool_triangles;
  m.arrow_count = 0;
  if (frame.force) {
    const ForceArrow& f = *frame.force;
    const float ratio = f.force_n.norm() / std::max(f.threshold_n, 1e-9f);
    const float scene = static_cast<float>(m.bounds.radius());
    // Green below 80 % of the threshold, amber up to it, red above.
    m.arrow_colour = ratio > 1.0f   ? Float3(0.92f, 0.16f, 0.12f)
                     : ratio > 0.8f ? Float3(0.98f, 0.68f, 0.12f)
                                    : Float3(0.25f, 0.85f, 0.35f);
    append_arrow(m.solid_mesh, f.origin_m, arrow_vector_m(f, m.bounds), 0.012f * scene);
    m.arrow_count = m.solid_mesh.triangles.size() - m.arrow_first;
  }
  glBindVertexArray(m.solid_vao);
  bytes += stream(GL_ARRAY_BUFFER, m.solid_position_vbo, m.solid_mesh.positions_m);
  bytes += stream(GL_ARRAY_BUFFER, m.solid_normal_vbo, m.solid_mesh.normals);
  bytes += stream(GL_ELEMENT_ARRAY_BUFFER, m.solid_ebo, m.solid_mesh.triangles);
  return bytes;
}

// The node cloud and the virtual tetrahedra's edges.
std::size_t Renderer::upload_overlays(const RenderFrame& frame) {
  Impl& m = *impl_;
  std::size_t bytes = 0;
  glBindVertexArray(m.node_vao);
  m.nodes = frame.node_points_m.size();
  m.tet_edges = frame.tet_edges.size();
  if (m.nodes > 0) bytes += stream(GL_ARRAY_BUFFER, m.node_vbo, frame.node_points_m);
  if (m.tet_edges > 0) bytes += stream(GL_ELEMENT_ARRAY_BUFFER, m.tet_ebo, frame.tet_edges);
  glBindVertexArray(0);
  return bytes;
}

// The pose, the projection and the lights of one picture.
struct Renderer::View {
  CameraPose pose;
  Eigen::Matrix4f view_proj;
  Vec3 towards_eye;
  Float3 key,
      fill;  // lights fixed to the camera: the key above-left of the eye, a weak fill from the lower right
};

void Renderer::draw(const OrbitCamera& camera, const RenderSettings& settings, unsigned framebuffer,
                    int width, int height) {
  Impl& m = *impl_;
  if (settings.measure) glFinish();
  const auto t0 = Clock::now();
  View view;
  view.pose = pose_for(camera, settings);
  const double aspect = static_cast<double>(width) / std::max(height, 1);
  view.view_proj = to_float(Eigen::Matrix4d(view.pose.projection(aspect) * view.pose.view()));
  view.towards_eye = (view.pose.eye_m - view.pose.target_m).normalized();
  const Vec3 cam_right = view.pose.forward().cross(view.pose.up).normalized();
  const Vec3 cam_up = cam_right.cross(view.pose.forward());
  view.key = to_float((-0.35 * cam_right + 0.45 * cam_up + 0.82 * view.towards_eye).normalized());
  view.fill = to_float((0.6 * cam_right - 0.3 * cam_up + 0.5 * view.towards_eye).normalized());

  glViewport(0, 0, width, height);
  glFrontFace(view.pose.mirror_x ? GL_CW : GL_CCW);
  glDisable(GL_CULL_FACE);
  if (settings.mode == ViewMode::fluoroscopy) {
    draw_fluoroscopy(view, settings, framebuffer, width, height);
  } else {
    draw_lit_background(settings, framebuffer);
    if (settings.show_surface && m.triangles > 0) draw_wall(view, camera, settings);
    draw_solids(view, settings);
    draw_overlays(view, settings);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glFrontFace(GL_CCW);
  if (settings.measure) glFinish();
  timing_.draw_ms = ms_since(t0);
}

// Fluoroscopy: the path lengths through wall, contrast-filled lumen and tools, accumulated in a float target
// and composited into grey by the attenuation law.
void Renderer::draw_fluoroscopy(const View& view, const RenderSettings& settings, unsigned framebuffer,
                                int width, int height) {
  Impl& m = *impl_;
  const Eigen::Matrix4f& view_proj = view.view_proj;
  const CameraPose& pose = view.pose;
  m.ensure_accumulation_target(width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, m.accum_fbo);
  glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  m.accumulate.use();
  m.accumulate.set("u_view_proj", view_proj);
  m.accumulate.set("u_source", to_float(pose.eye_m));
  m.accumulate.set("u_front_is_entry", 1);
  const FluoroSettings& f = settings.fluoro;
  if (settings.show_surface && m.triangles > 0) {
    // Wall solid (outward-oriented, closed) with mu_tissue, plus the lumen (the inner wall and the caps,
    // oriented inwards, hence negative) with mu_lumen: the inner wall carries mu_tissue - mu_lumen.
    const float mu_lumen = f.contrast_filled ? f.mu_contrast_per_m : f.mu_tissue_per_m;
    auto range = [&](std::size_t first, std::size_t count, float weight) {
      if (count == 0) return;
      m.accumulate.set("u_weight", weight);
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * count), GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(3 * first * sizeof(std::uint32_t)));
    };
    glBindVertexArray(m.lumen_vao);
    range(0, m.fluoro_wall, f.mu_tissue_per_m);
    range(m.fluoro_wall, m.fluoro_inner, f.mu_tissue_per_m - mu_lumen);
    range(m.fluoro_wall + m.fluoro_inner, m.fluoro_caps, -mu_lumen);
  }
  if (settings.show_tools && m.tool_triangles > 0) {
    m.accumulate.set("u_weight", f.mu_tool_per_m);
    glBindVertexArray(m.solid_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * m.tool_triangles), GL_UNSIGNED_INT, nullptr);
  }
  glDisable(GL_BLEND);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  m.composite.use();
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, m.accum_texture);
  m.composite.set("u_attenuation", 0);
  m.composite.set("u_background", f.background);
  m.composite.set("u_floor", f.floor);
  m.composite.set("u_vignette", f.vignette);
  m.composite.set("u_noise", f.noise);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, m.grain_texture);
  m.composite.set("u_grain", 1);
  const std::uint32_t seed = settings.frame_index * 2654435761u;
  glUniform2i(glGetUniformLocation(m.composite.id(), "u_grain_offset"), static_cast<int>(seed >> 24),
              static_cast<int>((seed >> 16) & 255u));
  glBindVertexArray(m.empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindTexture(GL_TEXTURE_2D, 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, 0);
}

void Renderer::draw_lit_background(const RenderSettings& settings, unsigned framebuffer) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glClearColor(settings.background.x(), settings.background.y(), settings.background.z(), 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_BLEND);
  // The wall and the tools are closed, outward-oriented solids: seen from outside their material only
  // front faces are visible, so culling the back faces halves the fragments. The cutaway opens the wall
  // (its cut shows back faces): no culling then.
  if (!settings.cutaway) {
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
  }
}

// The vessel wall: Blinn-Phong with the wall texture or the colour map, optionally cut away.
void Renderer::draw_wall(const View& view, const OrbitCamera& camera, const RenderSettings& settings) {
  Impl& m = *impl_;
  const Eigen::Matrix4f& view_proj = view.view_proj;
  const CameraPose& pose = view.pose;
  const Vec3& towards_eye = view.towards_eye;
  const Float3 &key = view.key, &fill = view.fill;
  m.surface.use();
  m.surface.set("u_view_proj", view_proj);
  m.surface.set("u_eye", to_float(pose.eye_m));
  m.surface.set("u_key_light", key);
  m.surface.set("u_fill_light", fill);
  m.surface.set("u_uv_aspect", m.uv_aspect);
  const bool colour_map = settings.show_colour_map && m.has_scalar;
  m.surface.set("u_colour_mode", colour_map ? 1 : 0);
  m.surface.set("u_scalar_range", Float2(m.scalar_info.min, m.scalar_info.max));
  const bool baked = m.wall_texture == 0;
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, baked ? m.baked_texture : m.wall_texture);
  m.surface.set("u_texture", 0);
  m.surface.set("u_baked", baked ? 1 : 0);
  m.surface.set("u_texture_cells", baked ? 1.0f : m.texture_repeats);
  if (settings.cutaway) {
    // Keep the half of the wall behind a plane through the target facing the camera. The plane contains
    // the superior axis (the camera's pitch is taken out of its normal), so a vessel lying in the
    // coronal plane is cut along its centre-line from any pitch.
    const Vec3 superior = camera.patient().superior.normalized();
    Vec3 n = towards_eye - towards_eye.dot(superior) * superior;
    n = n.norm() > 1e-6 ? Vec3(n.normalized()) : towards_eye;
    m.surface.set("u_clip_plane",
                  Eigen::Vector4f(static_cast<float>(-n.x()), static_cast<float>(-n.y()),
                                  static_cast<float>(-n.z()), static_cast<float>(n.dot(pose.target_m))));
    glEnable(GL_CLIP_DISTANCE0);
  } else {
    m.surface.set("u_clip_plane", Eigen::Vector4f(0.0f, 0.0f, 0.0f, 1.0f));
  }
  if (!m.has_uv) glVertexAttrib2f(2, 0.0f, 0.0f);
  if (!m.has_outer) glVertexAttrib1f(3, 1.0f);
  if (!m.has_scalar) glVertexAttrib1f(4, 0.0f);
  glBindVertexArray(m.surface_vao);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * m.triangles), GL_UNSIGNED_INT, nullptr);
  glDisable(GL_CLIP_DISTANCE0);
  glBindTexture(GL_TEXTURE_2D, 0);
}

// The tools, the instruments and the force arrow.
void Renderer::draw_solids(const View& view, const RenderSettings& settings) {
  Impl& m = *impl_;
  const Eigen::Matrix4f& view_proj = view.view_proj;
  const CameraPose& pose = view.pose;
  const Float3 &key = view.key, &fill = view.fill;
  const bool tools = settings.show_tools && m.tool_triangles > 0;
  const bool arrow = settings.show_force && m.arrow_count > 0;
  if (tools || arrow) {
    m.solid.use();
    m.solid.set("u_view_proj", view_proj);
    m.solid.set("u_eye", to_float(pose.eye_m));
    m.solid.set("u_key_light", key);
    m.solid.set("u_fill_light", fill);
    glBindVertexArray(m.solid_vao);
    if (tools) {
      m.solid.set("u_shininess", 60.0f);
      for (const auto& t : m.tool_draws) {
        m.solid.set("u_colour", t.colour);
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * t.count), GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(3 * t.first * sizeof(std::uint32_t)));
      }
    }
    if (arrow) {
      // On top of the wall: the arrow often starts at a contact point hidden behind it.
      glDisable(GL_DEPTH_TEST);
      m.solid.set("u_shininess", 30.0f);
      m.solid.set("u_colour", m.arrow_colour);
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * m.arrow_count), GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(3 * m.arrow_first * sizeof(std::uint32_t)));
      glEnable(GL_DEPTH_TEST);
    }
  }
}

// The node cloud and the virtual tetrahedra.
void Renderer::draw_overlays(const View& view, const RenderSettings& settings) {
  Impl& m = *impl_;
  const Eigen::Matrix4f& view_proj = view.view_proj;
  glDisable(GL_CULL_FACE);
  if ((settings.show_nodes && m.nodes > 0) || (settings.show_tets && m.tet_edges > 0)) {
    m.overlay.use();
    m.overlay.set("u_view_proj", view_proj);
    glBindVertexArray(m.node_vao);
    if (settings.show_tets && m.tet_edges > 0) {
      glEnable(GL_BLEND);
      glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
      m.overlay.set("u_colour", Eigen::Vector4f(0.55f, 0.85f, 1.0f, 0.35f));
      glDrawElements(GL_LINES, static_cast<GLsizei>(2 * m.tet_edges), GL_UNSIGNED_INT, nullptr);
      glDisable(GL_BLEND);
    }
    if (settings.show_nodes && m.nodes > 0) {
      glEnable(GL_PROGRAM_POINT_SIZE);
      m.overlay.set("u_point_size", 3.0f);
      m.overlay.set("u_colour", Eigen::Vector4f(1.0f, 0.9f, 0.3f, 1.0f));
      glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(m.nodes));
      glDisable(GL_PROGRAM_POINT_SIZE);
    }
  }
}

}  // namespace vascsim::render
