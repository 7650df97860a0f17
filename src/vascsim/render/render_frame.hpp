#pragma once
// What the renderer draws in one frame: a plain-data snapshot the simulation side fills and the render
// thread reads (through FrameExchange, never shared while being written). Everything is SI: positions in
// metres, forces in newtons. Floats, because that is what the GPU takes: the render thread uploads the
// arrays as they are.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vascsim/core/types.hpp"
#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim::render {

using Float3 = Eigen::Vector3f;
using Float2 = Eigen::Vector2f;

/// A rigid tool drawn as a capsule: a cylinder shaft from `back_m` to `tip_m` with a hemispherical cap at
/// the tip (if rounded_tip) and a flat end at the back. A catheter is a long shaft with a rounded tip.
struct ToolCapsule {
  Float3 back_m = Float3::Zero();
  Float3 tip_m = Float3::UnitZ();
  float radius_m = 1e-3f;
  bool rounded_tip = true;
  /// Colour in the lit view (linear RGB in [0, 1]); the tool is always strongly radio-opaque.
  Float3 colour = Float3(0.85f, 0.87f, 0.9f);
};

/// A flexible instrument (guidewire, catheter) drawn as a tube of `radius_m` swept along its centre-line, a
/// polyline through the rod's nodes, closed by flat ends. Like a tool it is strongly radio-opaque.
struct InstrumentTube {
  std::vector<Float3> centreline_m;  ///< at least two distinct points to be drawn
  float radius_m = 0.5e-3f;
  /// Colour in the lit view (linear RGB in [0, 1]).
  Float3 colour = Float3(0.35f, 0.78f, 0.95f);
};

/// The contact force on the tool, drawn as an arrow whose tail is at the contact point. Its colour turns
/// from green to red when |force_n| exceeds threshold_n (amber between 80 % and 100 % of it).
struct ForceArrow {
  Float3 origin_m = Float3::Zero();
  Float3 force_n = Float3::Zero();
  float threshold_n = 0.5f;
  /// Arrow length per newton. 0: automatic, a force equal to the threshold is drawn 0.3 x the radius of
  /// the frame's bounds long, so the arrow is readable at any vessel size.
  float length_per_newton_m = 0.0f;
};

/// A per-vertex scalar field shown as a colour map (displacement magnitude, von Mises stress, ...).
struct ScalarField {
  std::vector<float> values;  ///< one per surface vertex, in `unit`
  float min = 0.0f, max = 1.0f;
  std::string label;  ///< e.g. "displacement"
  std::string unit;   ///< e.g. "mm", "kPa" (values are shown as given)
};

struct RenderFrame {
  // --- The wall surface (the MLS-mapped surface of the current deformation) ---
  /// Bump whenever `triangles`, `uv` or `outer` change; positions/normals may change every frame.
  std::uint64_t topology_version = 0;
  std::vector<Float3> positions_m;
  /// Unit vertex normals (outward from the wall solid). Empty: the renderer computes them (area-weighted).
  std::vector<Float3> normals;
  /// Surface parameters: u along the vessel, v around it in [0, 1) (periodic: the seam may be shared).
  std::vector<Float2> uv;
  /// Triangles oriented outward from the wall solid (counter-clockwise seen from outside the wall).
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// Per vertex: 1 on the outer wall, 0 on the inner (lumen) wall. Empty: everything is outer.
  std::vector<std::uint8_t> outer;
  /// Length / circumference of the vessel, so the procedural texture has square cells (1: unknown).
  float uv_aspect = 1.0f;
  std::optional<ScalarField> scalar;

  // --- Overlays ---
  std::vector<Float3> node_points_m;                    ///< the point primitives (node cloud)
  std::vector<std::array<std::uint32_t, 2>> tet_edges;  ///< virtual tetrahedra edges into node_points_m

  // --- Tools and contact ---
  std::vector<ToolCapsule> tools;
  std::vector<InstrumentTube> instruments;
  std::optional<ForceArrow> force;

  // --- Bookkeeping ---
  std::uint64_t sequence = 0;  ///< incremented by the producer for every published frame
  double sim_time_s = 0.0;

  std::size_t vertex_count() const { return positions_m.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
};

/// Axis-aligned bounds. Empty frame: a unit box at the origin.
struct Bounds {
  Vec3 min = -Vec3::Ones(), max = Vec3::Ones();
  Vec3 centre() const { return 0.5 * (min + max); }
  double radius() const { return 0.5 * (max - min).norm(); }
};
/// Bounds of the surface, the tools and the instruments (what sets the arrow's automatic scale).
Bounds scene_bounds(const RenderFrame& frame);
/// scene_bounds() extended to the force arrow's head: what the camera frames.
Bounds frame_bounds(const RenderFrame& frame);
/// The arrow as drawn, m: force x length_per_newton_m, or with the automatic scale (see ForceArrow).
Float3 arrow_vector_m(const ForceArrow& arrow, const Bounds& scene);

/// Unit area-weighted vertex normals of `positions` over `triangles` (the renderer's fallback).
void compute_normals(const std::vector<Float3>& positions,
                     const std::vector<std::array<std::uint32_t, 3>>& triangles,
                     std::vector<Float3>& normals);

/// The edges of virtual tetrahedra, each once (smaller index first, sorted): the tet_edges overlay.
std::vector<std::array<std::uint32_t, 2>> tet_edge_list(const std::vector<Tet>& tets);

/// Throws InputError (one line naming the array and the first bad entry) if the arrays of the frame do
/// not match: sizes, indices out of range, non-finite positions.
void validate_frame(const RenderFrame& frame);

/// Copies double-precision geometry (e.g. a SweptVessel or an MLS surface) into the frame's float arrays.
void assign_positions(RenderFrame& frame, const Vec3Array& positions_m);
void assign_normals(RenderFrame& frame, const Vec3Array& normals);

}  // namespace vascsim::render
