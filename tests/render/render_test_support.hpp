#pragma once
// Shared pieces of the renderer's tests: a headless context, the demo vessel frame, and a CPU coverage
// rasteriser that gives the silhouette a picture must show (the expected area), independent of GL.

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "vascsim/render/camera.hpp"
#include "vascsim/render/demo_vessel.hpp"
#include "vascsim/render/gl_context.hpp"
#include "vascsim/render/renderer.hpp"
#include "vascsim/render/screenshot.hpp"
#include "vascsim/render/tool_geometry.hpp"

namespace vascsim::render::test {

/// Pixels whose centre lies inside at least one of `triangles` projected with `view_proj` (rows from the
/// top, as Image). Edge functions in double precision; both windings count.
inline std::vector<std::uint8_t> coverage(const std::vector<Float3>& positions,
                                          const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                          const Eigen::Matrix4d& view_proj, int width, int height) {
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(width) * height, 0);
  std::vector<Eigen::Vector2d> px(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector4d c = view_proj * positions[i].cast<double>().homogeneous();
    const Eigen::Vector2d ndc = c.head<2>() / c.w();
    px[i] = Eigen::Vector2d((0.5 * ndc.x() + 0.5) * width, (0.5 - 0.5 * ndc.y()) * height);
  }
  for (const auto& t : triangles) {
    const Eigen::Vector2d a = px[t[0]], b = px[t[1]], c = px[t[2]];
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (area == 0.0) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
      return (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
    };
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x + 0.5, y + 0.5);
        const double e0 = edge(a, b, p), e1 = edge(b, c, p), e2 = edge(c, a, p);
        const bool inside = area > 0 ? (e0 >= 0 && e1 >= 0 && e2 >= 0) : (e0 <= 0 && e1 <= 0 && e2 <= 0);
        if (inside) mask[static_cast<std::size_t>(y) * width + x] = 1;
      }
  }
  return mask;
}

inline std::size_t count(const std::vector<std::uint8_t>& mask) {
  std::size_t n = 0;
  for (auto m : mask) n += m;
  return n;
}

/// A picture against the silhouette its geometry implies (pixel counts and mean colours).
struct Silhouette {
  std::size_t drawn = 0, expected = 0, both = 0;
  Eigen::Vector3d mean_object = Eigen::Vector3d::Zero(), mean_background = Eigen::Vector3d::Zero();
  double relative_error() const {
    return expected == 0 ? 1.0
                         : std::abs(static_cast<double>(drawn) - static_cast<double>(expected)) / expected;
  }
  /// The picture shows the geometry: areas agree to 1 %, 99 % of the expected pixels are drawn, and the
  /// object's mean colour is at least 20 levels (of 255) from the background's.
  bool shows_geometry() const {
    return expected > 0 && relative_error() <= 0.01 && both >= 0.99 * expected &&
           (mean_object - mean_background).norm() > 20.0;
  }
};

/// Counts the pixels `is_object` calls drawn against the expected mask; mean colours of object and
/// background.
template <typename IsObject>
inline Silhouette compare(const Image& image, const std::vector<std::uint8_t>& expected, IsObject is_object) {
  Silhouette s;
  std::size_t n_bg = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      const Eigen::Vector3d c(p[0], p[1], p[2]);
      const bool drawn = is_object(x, y, p);
      const bool want = expected[static_cast<std::size_t>(y) * image.width + x] != 0;
      s.drawn += drawn;
      s.expected += want;
      s.both += drawn && want;
      if (drawn)
        s.mean_object += c;
      else {
        s.mean_background += c;
        ++n_bg;
      }
    }
  if (s.drawn > 0) s.mean_object /= static_cast<double>(s.drawn);
  if (n_bg > 0) s.mean_background /= static_cast<double>(n_bg);
  return s;
}

/// The catheter of a frame as one triangle mesh.
inline SolidMesh tool_mesh(const RenderFrame& frame) {
  SolidMesh m;
  for (const ToolCapsule& t : frame.tools) append_capsule(m, t);
  return m;
}

/// A headless context, a renderer and the demo vessel (about 10k triangles), framed by the orbit
/// camera. Small pictures keep the software renderer fast.
class HeadlessScene : public ::testing::Test {
 protected:
  static constexpr int kWidth = 480, kHeight = 300;

  void SetUp() override {
    ContextOptions o;
    o.width = kWidth;
    o.height = kHeight;
    o.headless = true;
    context = make_headless_context(o);
    renderer = std::make_unique<Renderer>();
    DemoVesselSpec spec;
    spec.target_triangles = 10000;
    demo = std::make_unique<DemoVessel>(spec);
    demo->fill(frame, 0.25);
    frame.sequence = 1;
    camera.fit(frame_bounds(frame));
    camera.zoom(2);
  }

  Image render(const RenderSettings& settings) {
    renderer->upload(frame);
    renderer->draw(camera, settings, context->draw_framebuffer(), kWidth, kHeight);
    context->finish_frame();
    return read_frame(*context);
  }

  Eigen::Matrix4d view_proj(const RenderSettings& settings) const {
    const CameraPose p = Renderer::pose_for(camera, settings);
    return p.projection(static_cast<double>(kWidth) / kHeight) * p.view();
  }

  std::unique_ptr<GlContext> context;
  std::unique_ptr<Renderer> renderer;
  std::unique_ptr<DemoVessel> demo;
  RenderFrame frame;
  OrbitCamera camera;
};

}  // namespace vascsim::render::test
