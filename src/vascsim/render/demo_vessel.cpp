#include "vascsim/render/demo_vessel.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vascsim/geometry/centerline.hpp"

namespace vascsim::render {

namespace {

// Wall triangles of a swept vessel with spacing h: 2 x 2 x nt x (nz - 1) on the two walls plus the end
// rings, nt = circumference / h, nz = length / h; the factor 3.6 instead of 4 matches the swept vessel's
// rounding of nt and nz (measured).
double spacing_for(const DemoVesselSpec& s, double length) {
  const double circumference = 2.0 * std::numbers::pi * s.outer_radius_m;
  return std::sqrt(3.6 * circumference * length / std::max(s.target_triangles, 100));
}

}  // namespace

DemoVessel::DemoVessel(const DemoVesselSpec& spec) : spec_(spec) {
  const Centerline cl = bent_centerline(spec.bend_radius_m, spec.bend_angle_deg, spec.leg_length_m);
  spacing_ = spacing_for(spec, cl.length());
  SweptVesselSpec vs;
  vs.outer_radius_m = spec.outer_radius_m;
  vs.wall_thickness_m = spec.wall_thickness_m;
  // The lattice spacing drives the surface resolution; the wall keeps its 3 node layers.
  vs.node_spacing_m = spacing_;
  vs.min_layers = 3;
  vessel_ = make_swept_vessel(cl, vs);

  const std::size_t nv = vessel_.surface_vertices.size();
  rest_.resize(nv);
  uv_.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    rest_[i] = vessel_.surface_vertices[i].cast<float>();
    uv_[i] = vessel_.uv[i].cast<float>();
  }
  triangles_.reserve(vessel_.triangles.size());
  for (const auto& t : vessel_.triangles)
    triangles_.push_back({static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                          static_cast<std::uint32_t>(t[2])});
  const std::size_t n_outer = static_cast<std::size_t>(vessel_.angular_nodes) * vessel_.axial_nodes;
  outer_.assign(nv, 0);
  std::fill(outer_.begin(), outer_.begin() + static_cast<std::ptrdiff_t>(std::min(n_outer, nv)), 1);

  // The catheter: straight outside the vessel along its entry direction, then along the centre-line,
  // drifting to the outer side of the bend until the tip touches the wall there.
  const double length = cl.length();
  const double s_tip = spec.tip_arc_fraction * length;
  const double lumen_r = spec.outer_radius_m - spec.wall_thickness_m;
  const double offset_max = lumen_r - spec.catheter_radius_m;
  auto outward = [&](double s) {
    const double h = 1e-4 * length;
    const Vec3 k = cl.tangent(std::min(s + h, length)) - cl.tangent(std::max(s - h, 0.0));
    return k.norm() > 1e-9 ? Vec3(-k.normalized()) : Vec3(-cl.frame(s).N);
  };
  const double s_bend = spec.leg_length_m;
  auto catheter_axis = [&](double s) -> Vec3 {
    if (s <= 0.0) return cl.position(0.0) + s * cl.tangent(0.0);
    const double f = std::clamp((s - s_bend * 0.6) / std::max(s_tip - s_bend * 0.6, 1e-9), 0.0, 1.0);
    const double w = f * f * (3.0 - 2.0 * f);
    return cl.position(s) + w * offset_max * outward(std::min(s, s_tip));
  };
  const double seg = std::max(1.5 * spec.catheter_radius_m, 0.01 * length);
  const double s0 = -spec.catheter_outside_m;
  const int n = std::max(2, static_cast<int>(std::ceil((s_tip - s0) / seg)));
  for (int i = 0; i < n; ++i) {
    ToolCapsule c;
    const double sa = s0 + (s_tip - s0) * i / n, sb = s0 + (s_tip - s0) * (i + 1) / n;
    c.back_m = catheter_axis(sa).cast<float>();
    c.tip_m = catheter_axis(sb).cast<float>();
    c.radius_m = static_cast<float>(spec.catheter_radius_m);
    c.rounded_tip = i == n - 1;
    c.colour = Float3(0.30f, 0.62f, 0.86f);  // a blue polymer catheter
    if (c.rounded_tip) {
      // The rounded tip's apex lies one radius beyond the last axis point.
      const Float3 dir = (c.tip_m - c.back_m).normalized();
      c.tip_m += dir * c.radius_m;
    }
    catheter_.push_back(c);
  }
  push_dir_ = outward(s_tip).cast<float>();
  contact_m_ = (cl.position(s_tip) + lumen_r * outward(s_tip)).cast<float>();

  if (spec.overlays) {
    for (const Vec3& p : vessel_.cloud.positions) node_points_.push_back(p.cast<float>());
    tet_edges_ = tet_edge_list(vessel_.cloud.tets);
  }
}

void DemoVessel::fill(RenderFrame& frame, double t_s, double depth_scale) const {
  const float depth = static_cast<float>(spec_.indent_depth_m * depth_scale *
                                         (0.75 + 0.25 * std::sin(2.0 * std::numbers::pi * t_s)));
  const float sigma = static_cast<float>(1.2 * spec_.outer_radius_m);
  const std::size_t nv = rest_.size();
  frame.topology_version = 1;
  frame.positions_m.resize(nv);
  if (!frame.scalar) frame.scalar.emplace();
  ScalarField& disp = *frame.scalar;
  disp.values.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const float r2 = (rest_[i] - contact_m_).squaredNorm();
    const float d = depth * std::exp(-r2 / (2.0f * sigma * sigma));
    frame.positions_m[i] = rest_[i] + d * push_dir_;
    disp.values[i] = d * 1e3f;
  }
  disp.min = 0.0f;
  disp.max = static_cast<float>(spec_.indent_depth_m * 1e3);
  disp.label = "displacement";
  disp.unit = "mm";
  compute_normals(frame.positions_m, triangles_, frame.normals);
  frame.uv = uv_;
  frame.triangles = triangles_;
  frame.outer = outer_;
  frame.uv_aspect = static_cast<float>(vessel_.length_m / (2.0 * std::numbers::pi * spec_.outer_radius_m));
  frame.node_points_m = node_points_;
  frame.tet_edges = tet_edges_;
  frame.tools = catheter_;
  ForceArrow arrow;
  arrow.origin_m = contact_m_ + depth * push_dir_;
  arrow.force_n = push_dir_ * static_cast<float>(spec_.stiffness_n_per_m) * depth;
  arrow.threshold_n = static_cast<float>(spec_.force_threshold_n);
  frame.force = arrow;
  frame.sim_time_s = t_s;
}

}  // namespace vascsim::render
