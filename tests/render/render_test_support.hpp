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
