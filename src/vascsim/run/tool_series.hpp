#pragma once
// The rigid tools (the catheter) as a VTK series of triangle surfaces, vtk/tools.pvd next to the wall's
// vtk/surface.pvd and written at the same output points, so ParaView and scripts/render_surface.py can show
// the tool where it is in every frame. Point data "displacement" is each vertex's motion from the tool's
// first written place, m.

#include <string>
#include <vector>

#include "vascsim/constraints/contact_constraint.hpp"
#include "vascsim/run/output_writer.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

class ToolSeries {
 public:
  /// Writes nothing when `enabled` is false or the scene has no tools.
  ToolSeries(const OutputWriter& out, const Scene& scene, bool enabled);
  bool active() const { return active_; }
  /// One frame: every tool at `placed` (scene order; the capsule's radius is replaced by the tool's own, so a
  /// contact margin, node_radius_m, is not drawn). `file_name` as the wall's frame, with "tools" for
  /// "surface".
  void add(double stamp, const std::string& file_name, const std::vector<constraints::Capsule>& placed);
  /// "vtk/tools.pvd", relative to the output folder ("" when inactive).
  std::string pvd_relative() const { return active_ ? series_.pvd_relative() : ""; }

 private:
  const Scene& scene_;
  bool active_ = false;
  VtkSeries series_;
  Vec3Array first_;  // the vertices of the first frame
};

/// Every tool of the scene at load factor s (the load-stepped and ramped runs).
std::vector<constraints::Capsule> tools_at(const Scene& scene, double s);

}  // namespace vascsim
