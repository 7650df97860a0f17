#pragma once
// Draws a RenderFrame with OpenGL 3.3 core: the lit view (vessel wall with a procedural texture or the
// colour map, tools, instruments, force arrow, node and tetrahedron overlays, optional cutaway) or the
// fluoroscopy view (grey X-ray projection of the contrast-filled lumen, the wall and the radio-opaque tools
// and instruments).
//
// Use on the render thread with the context current. upload() copies a frame into GPU buffers (only
// the per-frame arrays when the topology is unchanged); draw() renders the last uploaded frame into a
// framebuffer. Neither keeps a reference to the frame.

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "vascsim/render/camera.hpp"
#include "vascsim/render/render_frame.hpp"

namespace vascsim::render {

enum class ViewMode { lit, fluoroscopy };

/// Linear attenuation coefficients (1/m) and the picture's grey levels. The defaults are about 60 keV:
/// soft tissue (water) 20 /m, blood with iodinated contrast 300 /m (a 3 mm vessel transmits 40 %, an
/// aorta almost nothing), a radio-opaque catheter (braided, barium-filled) 1200 /m (a 6 Fr shaft transmits 9
/// %).
struct FluoroSettings {
  float mu_tissue_per_m = 20.0f;
  float mu_contrast_per_m = 300.0f;
  float mu_tool_per_m = 1200.0f;
  bool contrast_filled = true;  ///< false: the lumen holds blood only (mu_tissue)
  float background = 0.80f;     ///< grey with nothing in the beam
  float floor = 0.05f;          ///< grey behind an opaque object
  float vignette = 0.35f;       ///< darkening at the corners (0: none)
  float noise = 0.03f;          ///< quantum mottle (0: none)
};

struct RenderSettings {
  ViewMode mode = ViewMode::lit;
  double carm_lao_deg = 0.0;      ///< fluoroscopy: + LAO / - RAO, degrees
  double carm_cranial_deg = 0.0;  ///< fluoroscopy: + cranial / - caudal, degrees
  bool show_surface = true;
  bool show_tools = true;  ///< the rigid tools and the flexible instruments
  bool show_force = true;
  bool show_nodes = false;
  bool show_tets = false;
  bool show_colour_map = false;  ///< needs frame.scalar
  bool cutaway = false;          ///< lit: cut away the wall's half in front of a plane through the target
                                 ///< that contains the superior axis and faces the camera
  Float3 background = Float3(0.10f, 0.11f, 0.14f);  ///< lit view, sRGB
  FluoroSettings fluoro;
  /// glFinish() between the phases, so the timing split is what the GPU (llvmpipe: the CPU) spent; costs
  /// the overlap of CPU and GPU work, so only for measuring.
  bool measure = false;
  std::uint32_t frame_index = 0;  ///< seeds the fluoroscopy grain
};

/// Milliseconds of the last upload() and draw(). Without RenderSettings::measure they are the CPU time
/// to issue the calls, not the rendering time.
struct FrameTiming {
  double upload_ms = 0.0;
  double draw_ms = 0.0;
  std::size_t uploaded_bytes = 0;
};

class Renderer {
 public:
  Renderer();  ///< compiles the programs: needs a current OpenGL >= 3.3 core context
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Uses an image for the wall instead of the procedural texture (`repeats` tiles around the vessel).
  /// Throws InputError if the file is missing or unreadable.
  void set_wall_texture(const std::string& path, float repeats = 1.0f);
  void clear_wall_texture();

  /// Copies the frame to the GPU (validate_frame() first: throws InputError for inconsistent arrays).
  /// Index buffers, uv and the lumen caps are rebuilt only when topology_version changes.
  void upload(const RenderFrame& frame, bool measure = false);
  /// Draws the last uploaded frame into `framebuffer` (0: the window) of size width x height.
  void draw(const OrbitCamera& camera, const RenderSettings& settings, unsigned framebuffer, int width,
            int height);

  /// The camera pose draw() uses for these settings (lit: orbit; fluoroscopy: C-arm).
  static CameraPose pose_for(const OrbitCamera& camera, const RenderSettings& settings);

  const FrameTiming& timing() const { return timing_; }
  std::size_t triangle_count() const;
  std::size_t vertex_count() const;

 private:
  struct Impl;
  struct View;  // the pose, the projection and the lights of one picture
  // upload() in steps; each returns the bytes it sent.
  std::size_t upload_per_frame_arrays(const RenderFrame& frame);
  std::size_t upload_topology(const RenderFrame& frame);
  std::size_t upload_tools_and_arrow(const RenderFrame& frame);
  std::size_t upload_overlays(const RenderFrame& frame);
  void draw_fluoroscopy(const View& view, const RenderSettings& settings, unsigned framebuffer, int width,
                        int height);
  void draw_lit_background(const RenderSettings& settings, unsigned framebuffer);
  void draw_wall(const View& view, const OrbitCamera& camera, const RenderSettings& settings);
  void draw_solids(const View& view, const RenderSettings& settings);
  void draw_overlays(const View& view, const RenderSettings& settings);
  std::unique_ptr<Impl> impl_;
  FrameTiming timing_;
};

}  // namespace vascsim::render
