#pragma once
// A scene: everything one run needs, read and validated from a JSON file (docs/scene-format.md).
// Loading applies command-line overrides (--set path.to.key=value) before validation, so an override
// is checked exactly like a key in the file. The models' own settings blocks are read by the models'
// registry entries (model/registry.hpp); this folder holds only the schema, its validation and the
// overrides.

#include <any>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vascsim/geometry/centerline.hpp"
#include "vascsim/geometry/generators.hpp"
#include "vascsim/geometry/swept_vessel.hpp"
#include "vascsim/mapping/mls_map.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/model/problem.hpp"
#include "vascsim/model/rigid_obstacle.hpp"
#include "vascsim/rod/instrument.hpp"

namespace vascsim {

/// A vessel centre-line (geometry type "vessel").
struct CenterlineSpec {
  std::string type;                    ///< "straight", "bent", "s" or "polyline"
  double length_m = 0.0;               // straight
  double radius_of_curvature_m = 0.0;  // bent, s
  double angle_deg = 0.0;              // bent, s
  double leg_length_m = 0.0;           // bent, s: straight legs before and after the arcs
  Vec3Array points_m;                  // polyline: points the C1 curve passes through
};

/// An imported triangle mesh (geometry type "mesh").
struct MeshGeometrySpec {
  std::string file;            ///< resolved against the scene file's folder
  double units_m = 1.0;        ///< metres per file unit (1e-3 for a file in millimetres)
  std::string kind = "lumen";  ///< "lumen" (offset outward by the wall thickness) or "closed_wall"
  double wall_thickness_m = 0.0;
  double node_spacing_m = 0.0;
  int min_layers = 3;
};

struct GeometrySpec {
  std::string type;  ///< "tube", "vessel", "mesh", "box" or "beam"
  TubeSpec tube;     ///< tube; for "vessel" the radius, thickness, spacing and layers (length unused)
  bool lattice_angle_given =
      false;  ///< tube, vessel: the scene set lattice_angle_deg (else: the first wall patch's)
  /// tube, vessel: "strips" or "edges" chooses the lattice's counts around and along the vessel so that the
  /// first wall patch's strips, or its nodes' span, are the extent asked (geometry/lattice_fit; they go into
  /// tube.angular_nodes / axial_nodes); "none" keeps the counts of the spacing
  std::string fit_lattice_to_patch = "none";
  /// vessel: a graded lattice (geometry.refine); its s_center_m is refine_s_center_fraction of the
  /// centre-line's length when that is >= 0.
  WallRefinement refine;
  double refine_s_center_fraction = -1.0;
  /// vessel: geometry.refine.around, the obstacle the window is centred on (empty: the window's own centre),
  /// and that obstacle's tool point at rest (m; the catheter's tip, the sphere's centre).
  std::string refine_around;
  Vec3 refine_around_point_m = Vec3::Zero();
  CenterlineSpec centerline;
  MeshGeometrySpec mesh;
  BoxSpec box;
  // beam: a box from x = -(clamp_layers - 1) Delta to length, cross-section width x height
  double beam_length_m = 0.0, beam_width_m = 0.0, beam_height_m = 0.0;
  int beam_clamp_layers = 3;
};

/// The centre-line a vessel geometry describes.
Centerline build_centerline(const CenterlineSpec& spec);

struct SelectorSpec {
  std::string type;  ///< "box", "cylinder_end", "wall_patch", "surface_patch", "all"
  Vec3 min_m = Vec3::Zero(), max_m = Vec3::Zero();  // box
  std::string end = "start";                        // cylinder_end: "start" (s = 0) or "end" (s = L)
  double depth_m = 0.0;                             // cylinder_end: nodes within this arc length of the end
  std::string surface = "outer";                    // wall_patch, surface_patch: "outer" or "inner"
  double angle_center_deg = 0.0, angle_half_width_deg = 15.0;
  double s_center_m = 0.0, s_half_length_m = 0.0;  // wall_patch: arc length along the centre-line
  double s_center_fraction = -1.0;                 // wall_patch: centre as a fraction of the length (if >= 0)
  Vec3 centre_m = Vec3::Zero();                    // surface_patch: nodes within radius_m of centre_m
  double radius_m = 0.0;
};

struct RegionSpec {
  std::string name;
  SelectorSpec select;
  RegionBcType bc = RegionBcType::Probe;
  Vec3 vector = Vec3::Zero();  ///< displacement (m) or total force (N) at load factor 1
  Vec3 direction = Vec3::Zero();
  bool direction_inward =
      false;  ///< direction "inward": into the wall at the patch (wall_patch, surface_patch)
  double magnitude = 0.0;
  bool has_vector = false;
  double release_time_s =
      std::numeric_limits<double>::infinity();  ///< fixed/displacement: let go at this time
};

struct PointProbeSpec {
  std::string name;
  Vec3 position_m = Vec3::Zero();
  std::string component = "magnitude";  ///< "x", "y", "z" or "magnitude"
};

struct ReferenceSpec {
  std::string type;    ///< "" (none) or "timoshenko_cantilever"
  std::string region;  ///< the loaded region whose deflection is compared
};

/// A haptic session (docs/haptics.md): a device poses one tool through the 1 kHz haptic loop while a
/// device-driven model deforms the tissue. Present when the scene has a "haptics" block.
/// A haptic session keeps every tick in memory (the recording, about 200 bytes a tick): at most this many
/// ticks (duration_s x rate_hz; 5.5 hours at 1 kHz).
inline constexpr double kMaxSessionTicks = 2e7;

struct HapticsSpec {
  bool enabled = false;
  std::string tool;               ///< the obstacle the device poses ("" : the scene's only obstacle)
  std::string trajectory;         ///< scripted device: trajectory file (resolved against the scene's folder)
  std::string mode = "lockstep";  ///< "lockstep" (deterministic, one thread) or "realtime" (haptic thread)
  double rate_hz = 1000.0;        ///< haptic loop rate, Hz
  int ticks_per_step = 1;         ///< lockstep: one simulation step per this many ticks
  double duration_s = 0.0;        ///< 0: the trajectory's length, s
  double force_limit_n = 0.88;    ///< clamp of the sent force (device continuous limit), N
  double force_step_n = 0.1;      ///< largest change of the sent force per tick, N
  double force_scale = 1.0;       ///< device force = scale x tool force (scaled feedback for tiny vessels)
  double proxy_mass_kg = 0.005, coupling_stiffness_n_per_m = 500.0, coupling_damping_n_s_per_m = -1.0;
};

/// How the viewer shows the scene (`vascsim view`, docs/viewer.md). Every key is optional; headless runs
/// ignore the block.
struct ViewerSpec {
  std::string texture;  ///< wall texture image (resolved against the scene's folder); "" : procedural
  double texture_repeats = 1.0;  ///< copies of the image around the vessel
  /// The force arrow and the HUD turn red above this force on the tool, N. 0: the force at which the device
  /// clamps (haptics.force_limit_n / haptics.force_scale).
  double force_threshold_n = 0.0;
  /// The patient's axes in the scene frame (unit; anterior is made perpendicular to superior): the camera's
  /// up and home direction, the C-arm's rotation axes. The swept vessels lie along +z.
  Vec3 superior = Vec3::UnitZ();
  Vec3 anterior = Vec3::UnitY();
};

/// Where the tools meet the tissue (docs/model/22-contact.md; the top-level `contact` block).
struct ContactSpec {
  /// "nodes": the nodes are points the tools push (an active set); "embedded": the tools meet the wall's
  /// MLS-mapped surface, sampled between the nodes, through a penalty (section 22.5).
  bool embedded = false;
  /// embedded: the samples' shape functions (run/contact_surface_builder.hpp): "interpolated" the barycentric
  /// weights of their triangle's nodes, "quadratic" a quadratic fit of the surface's nodes round the sample
  /// (mapping/surface_quadratic_fit.hpp), both where the triangle's vertices are nodes; "mls" the MLS map of
  /// the rendered surface
  enum class Shape { Interpolated, Quadratic, Mls } shape_functions = Shape::Interpolated;
  double stiffness_pa_per_m =
      0.0;  ///< embedded: pressure per metre of penetration, Pa/m; 0: 100 E / mean spacing
  double sample_spacing_m =
      0.0;  ///< embedded: spacing of the surface's samples, m; 0: a third of its mean edge
};

/// "interpolated", "quadratic" or "mls": the name contact.shape_functions takes.
const char* shape_functions_name(ContactSpec::Shape shape);

struct OutputSpec {
  bool vtk = false;      ///< node cloud series vtk/nodes.pvd
  bool surface = false;  ///< surface series vtk/surface.pvd (MLS-mapped; vessels and lattices)
  int vtk_every = 1;
};

struct Scene {
  std::string file;  ///< path it was read from
  std::string name;
  std::string description;
  std::string model = "quasi_static";
  GeometrySpec geometry;
  Material material;
  std::string material_law = "svk";  ///< material.law; the law object itself is energy.law (null for svk)
  DiscretizationOptions discretization;
  EnergyOptions energy;
  std::vector<RegionSpec> regions;
  std::vector<PointProbeSpec> probes;
  Vec3 gravity_m_s2 = Vec3::Zero();
  std::vector<RigidObstacle> obstacles;  ///< rigid tools, for models that take tools
  ContactSpec contact;                   ///< how the tools meet the tissue
  /// A flexible instrument (guidewire, catheter) in the vessel's lumen, run by `vascsim navigate`
  /// (run/navigation.hpp); `vascsim run` simulates the wall alone.
  std::optional<rod::InstrumentSpec> instrument;
  /// The discretisation is the accurate wall configuration (quadratic basis, thickness reach, through-wall
  /// Gauss points) by the model's default: then contact.surface defaults to "embedded".
  bool accurate_wall_defaults = false;
  /// Every registered model's settings, as its registry entry read them from its block (defaults when the
  /// block is absent), keyed by model name: the scene's model uses its own, `--set model=...` another's.
  std::map<std::string, std::any> model_settings;
  ReferenceSpec reference;
  MlsMapOptions mapping;  ///< the surface map (output.surface)
  OutputSpec output;
  HapticsSpec haptics;
  ViewerSpec viewer;
  nlohmann::json resolved;  ///< the JSON after overrides (for summary.json)
  /// What the scene runs with but probably does not mean, one line each naming the file, the key and the fix:
  /// sizes no vessel has (a scene typed in millimetres), a lattice too coarse along its wall, an obstacle's
  /// node_radius_m that moves the contact to the nodes (docs/scene-format.md, "Reading rules"). `vascsim
  /// check` and `vascsim run` print them with the model's accuracy warnings (experiments/run_assessment.hpp).
  std::vector<std::string> warnings;

  /// The settings of model `name` as its settings struct S (e.g. scene.settings<XpbdSettings>("xpbd")).
  template <class S>
  const S& settings(const std::string& name) const {
    return std::any_cast<const S&>(model_settings.at(name));
  }
  /// The settings of the scene's own model.
  const std::any& own_model_settings() const { return model_settings.at(model); }
};

/// Applies one override "path.to.key=value" to a JSON document. The value is parsed as JSON when it
/// can be (numbers, true/false, arrays), else taken as a string. Array elements are addressed by
/// index ("regions.2.bc.type"). Throws InputError for a malformed override.
void apply_override(nlohmann::json& doc, const std::string& assignment);

/// Index of the obstacle named `name` in scene.obstacles; with an empty name, the scene's only obstacle.
/// Throws InputError naming the file and `where` (the key or option that named it) if there is no such
/// obstacle, none at all, or several and no name.
std::size_t find_tool(const Scene& scene, const std::string& name, const std::string& where);

/// Reads, overrides and validates a scene file. Throws InputError naming the file and key.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Validates an in-memory scene document (`file` is used in messages).
Scene parse_scene(const nlohmann::json& doc, const std::string& file);

}  // namespace vascsim
