#pragma once
// The wall surface of the current deformation in the viewer's frame: the body's render surface mapped from
// the node displacements by the MLS map (float, every frame), its normals, the displacement colour field (or
// on request the stress), and on request the node cloud and the virtual tetrahedra. Runs on the simulation
// thread (the producer); the topology (triangles, uv, outer flags) is copied into a frame slot only when the
// slot holds an older build's. fill_rest_surface() gives the same surface without a simulation, at rest.

#include <array>
#include <cstdint>
#include <vector>

#include "vascsim/render/render_frame.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/viewer/viewer_frame.hpp"

namespace vascsim::viewer {

/// Fills the frame's surface with `surface` at rest (a rigid wall, e.g. `vascsim navigate`'s): positions,
/// normals, triangles, uv (wrapped round `superior` when the surface has none), outer flags; bumps
/// topology_version.
void fill_rest_surface(const RenderSurface& surface, const Vec3& superior, render::RenderFrame& frame);

class SurfaceSnapshot {
 public:
  /// Takes the render surface and builds its MLS map for a (re)built simulation; `build` numbers it (the
  /// frames' topology_version). Throws InputError for a scene without a render surface.
  void rebuild(Simulation& simulation, std::uint64_t build);

  /// Fills the frame's surface for the model's current node positions: positions, normals, the displacement
  /// field (mm), and the topology if the frame's is older. False (frame untouched) if the state is not
  /// finite.
  bool fill(Simulation& simulation, render::RenderFrame& frame, PrepareTiming& timing);
  /// Replaces the colour field by the von Mises stress (kPa) of the Cauchy stress at every node, mapped to
  /// the surface like the displacement: the SVK stress of the node's Green strain with the material's E and
  /// nu (exact for the default SVK law; for another law, the stress of its small-strain moduli).
  void fill_stress(Simulation& simulation, render::RenderFrame& frame);
  /// The node cloud and the edges of the virtual tetrahedra (each edge once), or clears them.
  void fill_overlays(Simulation& simulation, bool nodes, bool tets, render::RenderFrame& frame);

  std::size_t triangle_count() const { return triangles_.size(); }
  /// The rest surface's bounding box, m (the scale of the scene).
  const Vec3& rest_min() const { return lo_; }
  const Vec3& rest_max() const { return hi_; }
  double radius_m() const { return 0.5 * (hi_ - lo_).norm(); }

 private:
  const MlsMap* map_ = nullptr;
  std::uint64_t build_ = 0;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<render::Float2> uv_;
  std::vector<std::uint8_t> outer_;
  std::vector<render::Float3> rest_;
  float uv_aspect_ = 1.0f;
  Vec3 lo_ = -Vec3::Ones(), hi_ = Vec3::Ones();
  std::vector<std::array<std::uint32_t, 2>> tet_edges_;  // built on first request
  std::vector<Eigen::Vector3f> displacement_;            // node displacements (scratch)
  Vec3Array node_stress_, surface_stress_;               // von Mises in x (scratch)
};

}  // namespace vascsim::viewer
