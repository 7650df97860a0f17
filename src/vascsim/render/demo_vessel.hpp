#pragma once
// A vessel to render without any simulation: a swept centre-line wall (geometry/swept_vessel.hpp) with
// a catheter advanced into it and a synthetic indentation where the catheter tip pushes the outer side
// of the bend. For the demo program, the renderer's tests and timing, until the viewer draws the
// simulation's own MLS surface.

#include <array>
#include <cstdint>
#include <vector>

#include "vascsim/geometry/swept_vessel.hpp"
#include "vascsim/render/render_frame.hpp"

namespace vascsim::render {

struct DemoVesselSpec {
  double outer_radius_m = 3e-3;
  double wall_thickness_m = 0.6e-3;
  double bend_radius_m = 20e-3;       ///< centre-line radius of curvature of the bend
  double bend_angle_deg = 90.0;       ///< bend towards +x in the x-z plane
  double leg_length_m = 15e-3;        ///< straight legs before and after the bend
  int target_triangles = 20000;       ///< the node spacing is chosen to give about this many wall triangles
  double catheter_radius_m = 1e-3;    ///< 6 Fr
  double catheter_outside_m = 12e-3;  ///< shaft length outside the vessel's entry
  double tip_arc_fraction = 0.65;     ///< the tip's arc length / centre-line length
  double indent_depth_m = 0.4e-3;     ///< peak outward displacement of the wall at the tip
  double force_threshold_n = 0.5;
  double stiffness_n_per_m = 1000.0;  ///< force = stiffness x indentation (synthetic)
  bool overlays = false;              ///< fill node points and tetrahedron edges
};

class DemoVessel {
 public:
  explicit DemoVessel(const DemoVesselSpec& spec);

  /// Fills every field of `frame` for time t: the indentation breathes with t (depth x (0.75 + 0.25
  /// sin(2 pi t))), so successive frames differ; t = 0.25 gives the full depth. `depth_scale` scales it.
  /// frame.sequence is left to the caller.
  void fill(RenderFrame& frame, double t_s, double depth_scale = 1.0) const;

  const SweptVessel& vessel() const { return vessel_; }
  const DemoVesselSpec& spec() const { return spec_; }
  /// The catheter segments (capsules) and the rest wall, for tests that compute expected pictures.
  const std::vector<ToolCapsule>& catheter() const { return catheter_; }
  double node_spacing_m() const { return spacing_; }

 private:
  DemoVesselSpec spec_;
  double spacing_ = 0.0;
  SweptVessel vessel_;
  std::vector<Float3> rest_;
  std::vector<Float2> uv_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<std::uint8_t> outer_;
  std::vector<ToolCapsule> catheter_;
  Float3 contact_m_ = Float3::Zero();  // on the inner wall, at the tip
  Float3 push_dir_ = Float3::UnitX();  // outward from the bend
  std::vector<Float3> node_points_;
  std::vector<std::array<std::uint32_t, 2>> tet_edges_;
};

}  // namespace vascsim::render
