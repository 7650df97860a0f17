#include "vascsim/scene/scene.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "vascsim/core/error.hpp"
#include "vascsim/core/json_file.hpp"
#include "vascsim/core/json_reader.hpp"
#include "vascsim/core/text.hpp"
#include "vascsim/geometry/lattice_fit.hpp"
#include "vascsim/model/materials/law_factory.hpp"
#include "vascsim/model/registry.hpp"

namespace vascsim {

namespace {

constexpr double kBig = 1e30;

// Names that become CSV column prefixes or folder names: a letter, then letters, digits, '_' or '-'.
bool is_identifier(const std::string& name, bool allow_dash = false) {
  return !name.empty() && std::isalpha(static_cast<unsigned char>(name[0])) &&
         std::all_of(name.begin(), name.end(), [&](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || (allow_dash && c == '-');
         });
}

// Wall cross-section keys shared by "tube" and "vessel".
void read_wall_section(JsonReader& g, TubeSpec& t) {
  t.outer_radius_m = g.required_number("outer_radius_m", 1e-7, 10.0);
  t.wall_thickness_m = g.required_number("wall_thickness_m", 1e-8, 10.0);
  if (t.wall_thickness_m >= t.outer_radius_m)
    g.fail("wall_thickness_m", fmt::format("value {} must be smaller than outer_radius_m = {}",
                                           t.wall_thickness_m, t.outer_radius_m));
  t.node_spacing_m = g.required_number("node_spacing_m", 1e-8, 10.0);
  t.min_layers = g.integer("min_layers", 3, 2, 100);
}

CenterlineSpec read_centerline(JsonReader c) {
  CenterlineSpec s;
  s.type = c.required_string("type", {"straight", "bent", "s", "polyline"});
  if (s.type == "straight") {
    s.length_m = c.required_number("length_m", 1e-7, 100.0);
  } else if (s.type == "bent" || s.type == "s") {
    s.radius_of_curvature_m = c.required_number("radius_of_curvature_m", 1e-7, 100.0);
    s.angle_deg = c.required_number("angle_deg", 1.0, s.type == "bent" ? 359.0 : 179.0);
    s.leg_length_m = c.number("leg_length_m", 0.0, 0.0, 100.0);
  } else {
    const auto* pts = c.raw("points_m");
    if (!pts) c.missing("points_m", "an array of at least two [x, y, z] points (m) is required");
    if (!pts->is_array() || pts->size() < 2)
      c.fail("points_m", "expected an array of at least two [x, y, z] points (m)");
    for (std::size_t k = 0; k < pts->size(); ++k) {
      const auto& p = (*pts)[k];
      if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
        c.fail("points_m", fmt::format("point {} is not [x, y, z] (three numbers, m)", k));
      const Vec3 v(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
      if (!v.allFinite()) c.fail("points_m", fmt::format("point {} is not finite", k));
      s.points_m.push_back(v);
    }
  }
  c.finish();
  return s;
}

MeshGeometrySpec read_mesh(JsonReader& g) {
  MeshGeometrySpec m;
  m.file = g.required_string("file");
  m.units_m = g.number("units_m", 1.0, 1e-9, 1e3);
  m.kind = g.string("kind", "lumen", {"lumen", "closed_wall"});
  m.wall_thickness_m = m.kind == "lumen" ? g.required_number("wall_thickness_m", 1e-8, 10.0) : 0.0;
  m.node_spacing_m = g.required_number("node_spacing_m", 1e-8, 10.0);
  m.min_layers = g.integer("min_layers", 3, 3, 100);
  // Relative to the scene file, so a scene runs from any working directory.
  const std::filesystem::path p(m.file);
  if (p.is_relative())
    m.file = (std::filesystem::path(g.file()).parent_path() / p).lexically_normal().string();
  return m;
}

// geometry.refine: a graded vessel lattice, fine over a window of the wall (docs/scene-format.md).
void read_refinement(JsonReader& g, GeometrySpec& s) {
  JsonReader r = g.object("refine");
  WallRefinement& w = s.refine;
  w.enabled = true;
  r.allow({"around", "s_center_m", "s_center_fraction"});  // each read only without another
  w.node_spacing_m = r.required_number("node_spacing_m", 1e-8, 10.0);
  if (w.node_spacing_m > s.tube.node_spacing_m)
    r.fail("node_spacing_m",
           fmt::format("{:.4g} m is coarser than geometry.node_spacing_m ({:.4g} m), the spacing "
                       "away from the window",
                       w.node_spacing_m, s.tube.node_spacing_m));
  if (r.has("around")) {
    // The window's centre is where the named obstacle stands (resolved once the obstacles are read).
    s.refine_around = r.required_string("around");
    for (const char* key : {"angle_center_deg", "s_center_m", "s_center_fraction"})
      if (r.has(key))
        r.fail(key, fmt::format("the window is centred on the obstacle '{}' (around); leave it out",
                                s.refine_around));
  }
  w.angle_center_deg = r.number("angle_center_deg", 0.0, -360.0, 360.0);
  w.angle_half_width_deg = r.required_number("angle_half_width_deg", 1e-6, 179.0);
  if (r.has("s_center_m") && r.has("s_center_fraction"))
    r.fail("s_center_m", "give s_center_m or s_center_fraction, not both");
  if (r.has("s_center_m"))
    w.s_center_m = r.required_number("s_center_m", 0.0, 100.0);
  else if (s.refine_around.empty())
    s.refine_s_center_fraction = r.number("s_center_fraction", 0.5, 0.0, 1.0);
  w.s_half_length_m = r.required_number("s_half_length_m", 1e-8, 100.0);
  w.margin_m = r.number("margin_m", 0.0, 0.0, 100.0);
  w.growth = r.number("growth", 1.2, 1.01, 3.0);
  r.finish();
  if (g.has("lattice_angle_deg"))
    g.fail("lattice_angle_deg", "a graded lattice (refine) places its own columns; leave it out");
  if (s.fit_lattice_to_patch != "none")
    g.fail("fit_lattice_to_patch",
           "a graded lattice (refine) puts its window's edges on nodes itself; use 'none'");
}

// A wall swept along a centre-line, with node layers through it (tube, vessel).
bool swept_wall(const std::string& geometry_type) {
  return geometry_type == "tube" || geometry_type == "vessel";
}

// The equilibrium models' discretisation defaults (wall supports, the stabiliser on a quadratic fit) apply on
// a swept wall, in the sound formulation, for the models whose capability `default_on_walls` says so.
bool wall_default(const Scene& sc, bool literal, bool ModelCapabilities::*default_on_walls) {
  return swept_wall(sc.geometry.type) && !literal && find_model(sc.model).capabilities.*default_on_walls;
}

GeometrySpec read_geometry(JsonReader g) {
  GeometrySpec s;
  s.type = g.required_string("type", {"tube", "vessel", "mesh", "box", "beam"});
  if (swept_wall(s.type)) {
    s.lattice_angle_given = g.has("lattice_angle_deg");
    s.tube.lattice_angle_deg = g.number("lattice_angle_deg", 0.0, -360.0, 360.0);
    s.fit_lattice_to_patch = g.string("fit_lattice_to_patch", "none", {"none", "strips", "edges"});
  }
  if (s.type == "tube") {
    read_wall_section(g, s.tube);
    s.tube.length_m = g.required_number("length_m", 1e-7, 100.0);
  } else if (s.type == "vessel") {
    read_wall_section(g, s.tube);
    if (s.tube.min_layers < 3)
      g.fail("min_layers",
             "a swept vessel needs at least 3 layers (docs/model/00-design-decisions.md, decision 2)");
    if (!g.has("centerline")) g.missing("centerline", "a centre-line object is required");
    s.centerline = read_centerline(g.object("centerline"));
    g.allow({"refine"});  // listed as allowed whether or not the scene has the block
    if (g.has("refine")) read_refinement(g, s);
  } else if (s.type == "mesh") {
    s.mesh = read_mesh(g);
  } else if (s.type == "box") {
    g.allow({"min_m", "max_m"});  // neither is taken for a misspelling of the other
    s.box.min_m = g.required_vec3("min_m");
    s.box.max_m = g.required_vec3("max_m");
    if (!((s.box.max_m - s.box.min_m).array() > 0.0).all())
      g.fail("max_m", "must exceed min_m along every axis");
    const double spacing = g.required_number("node_spacing_m", 1e-8, 10.0);
    const Vec3 ext = s.box.max_m - s.box.min_m;
    for (int a = 0; a < 3; ++a) {
      const double cells = std::round(ext[a] / spacing);
      if (cells > 1e6)
        g.fail("node_spacing_m", fmt::format("gives {:.3g} cells along an axis; the limit is 1e6", cells));
      s.box.cells[a] = std::max(1, static_cast<int>(cells));
    }
    s.box.jitter = g.number("jitter", 0.0, 0.0, 0.25);
    s.box.seed = static_cast<std::uint64_t>(g.integer("seed", 1, 0, 1 << 30));
  } else {
    s.beam_length_m = g.required_number("length_m", 1e-7, 100.0);
    s.beam_width_m = g.required_number("width_m", 1e-8, 100.0);
    s.beam_height_m = g.required_number("height_m", 1e-8, 100.0);
    const double spacing = g.required_number("node_spacing_m", 1e-8, 10.0);
    s.beam_clamp_layers = g.integer("clamp_layers", 3, 1, 20);
    for (double extent : {s.beam_width_m, s.beam_height_m, s.beam_length_m})
      if (extent / spacing > 1e6) g.fail("node_spacing_m", "gives more than 1e6 cells along an axis");
    // Cells of equal edge Delta across the width (the cross-section sets Delta); length rounded to it.
    const int nw = std::max(1, static_cast<int>(std::lround(s.beam_width_m / spacing)));
    const double delta = s.beam_width_m / nw;
    const int nh = std::max(1, static_cast<int>(std::lround(s.beam_height_m / delta)));
    const int nl = std::max(1, static_cast<int>(std::lround(s.beam_length_m / delta)));
    s.box.min_m = Vec3(-(s.beam_clamp_layers - 1) * delta, 0.0, 0.0);
    s.box.max_m = Vec3(nl * delta, s.beam_width_m, s.beam_height_m);
    s.box.cells = Eigen::Vector3i(nl + s.beam_clamp_layers - 1, nw, nh);
    s.beam_length_m = nl * delta;
  }
  if (s.type == "box" || s.type == "beam") {
    const double nodes = (s.box.cells.cast<double>() + Vec3::Ones()).prod();
    if (nodes > 5e7) g.fail("node_spacing_m", fmt::format("gives {:.3g} nodes; the limit is 5e7", nodes));
  }
  g.finish();
  return s;
}

SelectorSpec read_selector(JsonReader r) {
  SelectorSpec s;
  s.type = r.required_string("type", {"box", "cylinder_end", "wall_patch", "surface_patch", "all"});
  if (s.type == "box") {
    s.min_m = r.vec3("min_m", Vec3::Constant(-kBig));
    s.max_m = r.vec3("max_m", Vec3::Constant(kBig));
  } else if (s.type == "cylinder_end") {
    s.end = r.required_string("end", {"start", "end"});
    s.depth_m = r.number("depth_m", 0.0, 0.0, 100.0);
  } else if (s.type == "wall_patch") {
    r.allow({"s_center_m", "z_center_m", "s_half_length_m", "z_half_length_m",
             "s_center_fraction"});  // alternatives
    s.surface = r.string("surface", "outer", {"outer", "inner"});
    s.angle_center_deg = r.number("angle_center_deg", 0.0, -360.0, 360.0);
    s.angle_half_width_deg = r.required_number("angle_half_width_deg", 0.0, 180.0);
    // s_* is the arc length along the centre-line; z_* is its older name (a straight tube's z).
    for (const char* k : {"center_m", "half_length_m"}) {
      const std::string sk = std::string("s_") + k, zk = std::string("z_") + k;
      if (r.has(sk) && r.has(zk)) r.fail(zk, fmt::format("give {} or {} (its older name), not both", sk, zk));
    }
    const std::string c = r.has("z_center_m") ? "z_center_m" : "s_center_m";
    const std::string h = r.has("z_half_length_m") ? "z_half_length_m" : "s_half_length_m";
    if (r.has("s_center_fraction")) {
      if (r.has(c)) r.fail("s_center_fraction", fmt::format("give {} or s_center_fraction, not both", c));
      s.s_center_fraction = r.required_number("s_center_fraction", 0.0, 1.0);
    } else {
      s.s_center_m = r.required_number(c, -100.0, 100.0);
    }
    s.s_half_length_m = r.required_number(h, 0.0, 100.0);
  } else if (s.type == "surface_patch") {
    s.surface = r.string("surface", "outer", {"outer", "inner"});
    s.centre_m = r.required_vec3("centre_m");
    s.radius_m = r.required_number("radius_m", 0.0, 100.0);
  }
  r.finish();
  return s;
}

// A direction: an array of three numbers (normalised) or the word "inward" (wall patches).
void read_direction(JsonReader& r, const std::string& key, RegionSpec& reg) {
  const auto* v = r.raw(key);
  if (!v) return;
  if (v->is_string()) {
    if (v->get<std::string>() != "inward") r.fail(key, "expected [x, y, z] or \"inward\"");
    if (reg.select.type != "wall_patch" && reg.select.type != "surface_patch")
      r.fail(key, "\"inward\" is only defined for wall_patch and surface_patch selectors");
    reg.direction_inward = true;
    return;
  }
  const Vec3 d = r.vec3(key, Vec3::Zero());
  if (!(d.norm() > 0.0)) r.fail(key, "the direction must not be the zero vector");
  reg.direction = d.normalized();
}

RegionSpec read_region(JsonReader r) {
  RegionSpec reg;
  reg.name = r.required_string("name");
  if (!is_identifier(reg.name))
    r.fail("name",
           fmt::format("'{}' is not allowed; use letters, digits and '_' (it names CSV columns)", reg.name));
  if (!r.has("select")) r.missing("select", "a selector object is required");
  reg.select = read_selector(r.object("select"));
  JsonReader bc = r.object("bc");
  const std::string type = bc.string("type", "probe", {"fixed", "displacement", "force", "probe"});
  const bool is_disp = type == "displacement", is_force = type == "force";
  reg.bc = type == "fixed" ? RegionBcType::Fixed
           : is_disp       ? RegionBcType::Displacement
           : is_force      ? RegionBcType::Force
                           : RegionBcType::Probe;
  if (is_disp || is_force) {
    const std::string vkey = is_disp ? "vector_m" : "vector_n";
    const std::string mkey = is_disp ? "magnitude_m" : "magnitude_n";
    bc.allow({is_disp ? "vector_m" : "vector_n", is_disp ? "magnitude_m" : "magnitude_n", "direction"});
    if (bc.has(vkey)) {
      if (bc.has(mkey) || bc.has("direction"))
        bc.fail(vkey, fmt::format("give either {} or direction + {}, not both", vkey, mkey));
      reg.vector = bc.vec3(vkey, Vec3::Zero());
      reg.has_vector = true;
      if (reg.vector.norm() > 0.0) reg.direction = reg.vector.normalized();
    } else {
      if (!bc.has("direction")) bc.missing("direction", fmt::format("give {} or direction + {}", vkey, mkey));
      read_direction(bc, "direction", reg);
      reg.magnitude = bc.required_number(mkey, -kBig, kBig);
    }
  }
  if (reg.bc == RegionBcType::Fixed || reg.bc == RegionBcType::Displacement) bc.allow({"release_time_s"});
  if (bc.has("release_time_s")) {
    if (reg.bc != RegionBcType::Fixed && reg.bc != RegionBcType::Displacement)
      bc.fail("release_time_s", "only a fixed or displacement region can be released");
    reg.release_time_s = bc.required_number("release_time_s", 0.0, 1e4);
  }
  bc.finish();
  if (!is_disp && !is_force) read_direction(r, "direction", reg);
  r.finish();
  return reg;
}

void read_material(JsonReader& root, Scene& sc) {
  JsonReader mat = root.object("material");
  sc.material_law = mat.string("law", "svk", materials::hyperelastic_law_names());
  nlohmann::json law_parameters = nlohmann::json::object();
  if (sc.material_law == "svk" || sc.material_law == "neo_hookean") {
    sc.material.youngs_modulus_pa = mat.number("youngs_modulus_pa", 0.5e6, 1e-6, 1e12);
    // >= 0: the point-primitive energy splits lambda into a volume term and lambda - k_v, both >= 0.
    sc.material.poisson_ratio = mat.number("poisson_ratio", 0.45, 0.0, 0.499);
    law_parameters = {{"youngs_modulus_pa", sc.material.youngs_modulus_pa},
                      {"poisson_ratio", sc.material.poisson_ratio}};
  } else if (sc.material_law == "mooney_rivlin") {
    mat.allow({"c10_pa", "c01_pa"});  // one transposition apart: neither is the other misspelt
    for (const char* k : {"c10_pa", "c01_pa"}) law_parameters[k] = mat.required_number(k, 0.0, 1e12);
    law_parameters["bulk_modulus_pa"] = mat.required_number("bulk_modulus_pa", 1e-6, 1e15);
  } else {  // hgo
    law_parameters["shear_modulus_pa"] = mat.required_number("shear_modulus_pa", 1e-6, 1e12);
    law_parameters["bulk_modulus_pa"] = mat.required_number("bulk_modulus_pa", 1e-6, 1e15);
    law_parameters["k1_pa"] = mat.required_number("k1_pa", 0.0, 1e12);
    law_parameters["k2"] = mat.required_number("k2", 0.0, 1e4);
    law_parameters["fibre_angle_deg"] = mat.required_number("fibre_angle_deg", 0.0, 90.0);
  }
  sc.material.density_kg_m3 = mat.number("density_kg_m3", 1060.0, 1e-3, 1e5);
  mat.finish();
  if (sc.material_law != "svk") {
    try {
      sc.energy.law = materials::make_hyperelastic_law(sc.material_law, law_parameters);
    } catch (const InputError& e) {
      mat.fail("law", e.what());
    }
    // The discretisation, the stability estimates and the preconditioner use E and nu: those of the law at
    // small strain (for hgo, of the ground matrix).
    const double mu = sc.energy.law->small_strain_shear_modulus(),
                 kappa = sc.energy.law->small_strain_bulk_modulus();
    sc.material.youngs_modulus_pa = 9.0 * kappa * mu / (3.0 * kappa + mu);
    sc.material.poisson_ratio = (3.0 * kappa - 2.0 * mu) / (2.0 * (3.0 * kappa + mu));
    if (!(sc.material.poisson_ratio < 0.4999))
      mat.fail("bulk_modulus_pa",
               fmt::format("gives a Poisson ratio of {:.6f} at small strain; it must be below 0.4999 "
                           "(lower the bulk modulus)",
                           sc.material.poisson_ratio));
    if (!(sc.material.poisson_ratio >= 0.0))
      mat.fail("bulk_modulus_pa",
               fmt::format("gives a Poisson ratio of {:.6f} at small strain; the point-primitive "
                           "energy needs it >= 0 (a bulk modulus >= 2/3 of the shear modulus)",
                           sc.material.poisson_ratio));
  }
}

void read_discretization(JsonReader& root, bool literal, Scene& sc) {
  JsonReader disc = root.object("discretization");
  sc.discretization.support_radius_factor = disc.number("support_radius_factor", 2.0, 1.01, 5.0);
  sc.discretization.min_neighbours = disc.integer("min_neighbours", 12, 4, 200);
  sc.discretization.min_eigen_ratio = disc.number("min_eigen_ratio", 1e-3, 1e-12, 1.0);
  sc.discretization.max_growths = disc.integer("max_growths", 3, 0, 10);
  // Supports that follow the wall wherever a lattice has node layers through one
  // (docs/model/03-neighbourhoods.md section 3.1), for the models that ask for it: against the FEM references
  // they converge to the same answer as isotropic ones and halve the error at coarse resolutions. The paper's
  // kernel is isotropic.
  const bool wall_support = wall_default(sc, literal, &ModelCapabilities::wall_support_default);
  const char* support_default = wall_support ? "wall" : "isotropic";
  sc.discretization.support = disc.string("support", support_default, {"isotropic", "wall"}) == "wall"
                                  ? DiscretizationOptions::Support::Wall
                                  : DiscretizationOptions::Support::Isotropic;
  const bool on_wall = sc.discretization.support == DiscretizationOptions::Support::Wall;
  // The models that ask for it get, on such a wall, the configuration docs/validation.md ("Gauss points over
  // the wall's cells") finds within about 2 % of the FEM references at the default resolutions and within 5 %
  // at a few thousand nodes: the quadratic basis, supports that reach through the wall's thickness and 2 x 2
  // x 2 Gauss points over each node's cell of the wall (docs/model/ sections 3.2, 4.4, 5.1).
  const bool accurate = on_wall && wall_default(sc, literal, &ModelCapabilities::accurate_wall_default);
  const std::string basis =
      disc.string("basis", accurate ? "quadratic" : "linear", {"linear", "quadratic", "wall_quadratic"});
  sc.discretization.basis = basis == "quadratic"        ? GradientBasis::Quadratic
                            : basis == "wall_quadratic" ? GradientBasis::WallQuadratic
                                                        : GradientBasis::Linear;
  const bool accurate_fit = accurate && sc.discretization.basis == GradientBasis::Quadratic;
  sc.discretization.wall_reach =
      disc.string("wall_reach", accurate_fit ? "thickness" : "layers", {"layers", "thickness"}) == "thickness"
          ? DiscretizationOptions::WallReach::Thickness
          : DiscretizationOptions::WallReach::Layers;
  if (sc.discretization.wall_reach == DiscretizationOptions::WallReach::Thickness && !on_wall)
    disc.fail("wall_reach",
              "'thickness' shapes a support that follows the wall and needs discretization.support "
              "'wall' (a geometry of type 'tube' or 'vessel')");
  const std::string quadrature =
      disc.string("wall_quadrature", accurate_fit ? "gauss_cell" : "nodes", {"nodes", "gauss", "gauss_cell"});
  const bool gauss = quadrature != "nodes";
  sc.discretization.wall_quadrature = quadrature == "gauss_cell"
                                          ? DiscretizationOptions::WallQuadrature::GaussCell
                                      : gauss ? DiscretizationOptions::WallQuadrature::Gauss
                                              : DiscretizationOptions::WallQuadrature::Nodes;
  if (gauss && !fits_curvature(sc.discretization.basis))
    disc.fail("wall_quadrature",
              fmt::format("'{}' evaluates each node's fit across its cell of the wall and needs "
                          "discretization.basis 'quadratic' or 'wall_quadratic'",
                          quadrature));
  if (gauss && !on_wall)
    disc.fail("wall_quadrature",
              fmt::format("'{}' places points in the wall and needs discretization.support 'wall' "
                          "(a geometry of type 'tube' or 'vessel')",
                          quadrature));
  // The quadratic basis's partner is the Simpson rule wherever the lattice has layers
  // (docs/model/04-volumes.md): with the tet partition's trapezoid weights it overestimates a bending field's
  // energy by half. Through-wall Gauss points integrate bending exactly themselves, over the tet partition's
  // volumes.
  const bool layered = sc.geometry.type != "mesh";
  const char* volume_default = literal ? "mueller_kernel"
                               : fits_curvature(sc.discretization.basis) && layered && !gauss
                                   ? "simpson"
                                   : "tet_partition";
  const std::string volume =
      disc.string("volume", volume_default, {"tet_partition", "mueller_kernel", "simpson"});
  if (volume == "simpson" && !layered)
    disc.fail("volume",
              "'simpson' needs a lattice with node layers (geometry type 'tube', 'vessel', 'box' or "
              "'beam'); use 'tet_partition'");
  if (gauss && volume != "tet_partition")
    disc.fail("volume",
              fmt::format("Gauss points (wall_quadrature '{}') integrate across the wall themselves and "
                          "weigh the tet partition's volumes; use 'tet_partition'",
                          quadrature));
  sc.discretization.volume = volume == "tet_partition"    ? VolumeRule::TetPartition
                             : volume == "mueller_kernel" ? VolumeRule::MuellerKernel
                                                          : VolumeRule::Simpson;
  sc.accurate_wall_defaults = accurate_fit && gauss;
  if (sc.discretization.basis == GradientBasis::WallQuadratic &&
      sc.discretization.support != DiscretizationOptions::Support::Wall)
    disc.fail("basis",
              "'wall_quadratic' fits in the frame of the wall and needs discretization.support 'wall' (a "
              "geometry of type 'tube' or 'vessel'); use 'linear' or 'quadratic'");
  // The through-wall cube (docs/model/05-local-fit.md section 5.3): part of the quadratic fit's default on
  // walls, where the two contact cases with converged FEM references ask for it; it changes nothing on a wall
  // of three layers.
  sc.discretization.wall_cube = disc.boolean("wall_cube", accurate_fit);
  if (sc.discretization.wall_cube && (sc.discretization.basis != GradientBasis::Quadratic || !on_wall))
    disc.fail("wall_cube",
              "the through-wall cube extends the quadratic fit on a wall and needs discretization.basis "
              "'quadratic' and support 'wall' (a geometry of type 'tube' or 'vessel')");
  // The cubics with a through-wall factor beside the cube (docs/model/05-local-fit.md section 5.4): more
  // accurate at the default resolutions, less at coarse ones, so not the default.
  const bool cell_points = quadrature == "gauss_cell";
  const std::string cubics = disc.string("wall_cubics", "cube", {"cube", "through_wall"});
  sc.discretization.wall_cubics = cubics == "through_wall" ? DiscretizationOptions::WallCubics::ThroughWall
                                                           : DiscretizationOptions::WallCubics::Cube;
  if (cubics == "through_wall" && !sc.discretization.wall_cube)
    disc.fail("wall_cubics",
              "'through_wall' extends the through-wall cube and needs discretization.wall_cube true");
  if (cubics == "through_wall" && !cell_points)
    disc.fail("wall_cubics",
              fmt::format("'through_wall' needs Gauss points over each node's cell (wall_quadrature "
                          "'gauss_cell', not '{}'): the cubics' gradients vary along the wall",
                          quadrature));
  sc.discretization.quadratic_min_neighbours = disc.integer("quadratic_min_neighbours", 18, 9, 200);
  sc.discretization.quadratic_min_eigen_ratio = disc.number("quadratic_min_eigen_ratio", 1e-6, 1e-14, 1.0);
  disc.finish();
}

void read_energy(JsonReader& root, bool literal, Scene& sc) {
  JsonReader en = root.object("energy");
  const std::shared_ptr<const materials::HyperelasticLaw> law = sc.energy.law;
  sc.energy.strain =
      en.string("strain", literal ? "mueller_no_half" : "green", {"green", "mueller_no_half"}) == "green"
          ? StrainMeasure::GreenHalf
          : StrainMeasure::MuellerNoHalf;
  sc.energy.stabilizer_alpha = en.number("stabilizer_alpha", literal ? 0.0 : 0.1, 0.0, 10.0);
  // On a wall with node layers the equilibrium models' stabiliser leaves bending to the strain energy
  // (docs/model/09-volume-term-and-stabiliser.md section 9.3): the linear fit's residuals of a bending field
  // are not zero-energy modes, and penalising them stiffened the vein at its real-time resolution by 2.4-5 %
  // against the FEM references.
  const bool quadratic_default = wall_default(sc, literal, &ModelCapabilities::quadratic_stabilizer_default);
  sc.energy.stabilizer_fit = en.string("stabilizer_fit", quadratic_default ? "quadratic" : "basis",
                                       {"basis", "quadratic"}) == "quadratic"
                                 ? StabilizerFit::Quadratic
                                 : StabilizerFit::Basis;
  const double lambda = sc.material.lame_lambda();
  sc.energy.volume_stiffness_pa = en.number("volume_stiffness_pa", 0.0, 0.0, std::max(lambda, 0.0));
  en.finish();
  sc.energy.law = law;
  if (law && sc.energy.strain != StrainMeasure::GreenHalf)
    en.fail("strain", fmt::format("the literal strain applies to material law 'svk' only (law is '{}')",
                                  sc.material_law));
}

// A patch of +-w deg is symmetric and w wide only if its centre lies on a lattice line. Unless the scene
// sets geometry.lattice_angle_deg, the tube/vessel lattice is turned (by less than half a column) so that a
// line runs through the first wall patch's centre. With geometry.fit_lattice_to_patch the counts around and
// along the vessel are chosen too, so that the patch's strips or its nodes' span are the extent asked.
void align_lattice_to_first_patch(JsonReader& root, Scene& sc) {
  GeometrySpec& g = sc.geometry;
  if (!swept_wall(g.type)) return;
  const auto patch = std::find_if(sc.regions.begin(), sc.regions.end(),
                                  [](const RegionSpec& r) { return r.select.type == "wall_patch"; });
  if (g.fit_lattice_to_patch == "none") {
    if (!g.lattice_angle_given && patch != sc.regions.end())
      g.tube.lattice_angle_deg = patch->select.angle_center_deg;
    return;
  }
  if (patch == sc.regions.end())
    root.fail("geometry.fit_lattice_to_patch", "there is no wall_patch region to fit the lattice to");
  if (g.lattice_angle_given)
    root.fail("geometry.lattice_angle_deg",
              "fit_lattice_to_patch sets the lattice's phase; leave lattice_angle_deg out");
  const double length = g.type == "tube" ? g.tube.length_m : build_centerline(g.centerline).length();
  const SelectorSpec& p = patch->select;
  const PatchExtent extent{p.angle_center_deg, p.angle_half_width_deg,
                           p.s_center_fraction >= 0.0 ? p.s_center_fraction * length : p.s_center_m,
                           p.s_half_length_m};
  const LatticeFit fit = fit_lattice_to_patch(
      g.tube, extent, length, g.fit_lattice_to_patch == "edges" ? PatchFit::Edges : PatchFit::Strips);
  g.tube.angular_nodes = fit.angular_nodes;
  g.tube.axial_nodes = fit.axial_nodes;
  g.tube.lattice_angle_deg = fit.lattice_angle_deg;
  spdlog::info("region '{}': {}", patch->name, fit.summary);
}

void read_regions(JsonReader& root, Scene& sc) {
  for (auto& r : root.array_of_objects("regions", false)) sc.regions.push_back(read_region(r));
  for (std::size_t a = 0; a < sc.regions.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (sc.regions[a].name == sc.regions[b].name)
        root.fail(fmt::format("regions.{}.name", a),
                  fmt::format("duplicate region name '{}'", sc.regions[a].name));
}

void read_probes(JsonReader& root, Scene& sc) {
  for (auto& p : root.array_of_objects("probes", false)) {
    PointProbeSpec ps;
    ps.name = p.required_string("name");
    if (!is_identifier(ps.name))
      p.fail("name", fmt::format("'{}' is not allowed; use letters, digits and '_' (it names a CSV column)",
                                 ps.name));
    for (const auto& r : sc.regions)
      if (r.name == ps.name) p.fail("name", fmt::format("'{}' is already a region name", ps.name));
    for (const auto& q : sc.probes)
      if (q.name == ps.name) p.fail("name", fmt::format("duplicate probe name '{}'", ps.name));
    ps.position_m = p.required_vec3("position_m");
    ps.component = p.string("component", "magnitude", {"x", "y", "z", "magnitude"});
    p.finish();
    sc.probes.push_back(ps);
  }
}

// geometry.refine.around: the named obstacle's tool point at rest, which build_body projects onto the
// centre-line.
void centre_refinement_on_tool(JsonReader& root, Scene& sc) {
  GeometrySpec& g = sc.geometry;
  if (g.refine_around.empty()) return;
  for (const RigidObstacle& o : sc.obstacles)
    if (o.name == g.refine_around) {
      g.refine_around_point_m = o.tool_point_m;
      return;
    }
  root.fail("geometry.refine.around",
            fmt::format("no obstacle named '{}'{}", g.refine_around,
                        sc.obstacles.empty() ? " (the scene has no obstacles)" : ""));
}

void read_tools(JsonReader& root, Scene& sc) {
  for (auto& o : root.array_of_objects("obstacles", false)) {
    RigidObstacle ob;
    ob.name = o.required_string("name");
    if (!is_identifier(ob.name))
      o.fail("name",
             fmt::format("'{}' is not allowed; use letters, digits and '_' (it names CSV columns)", ob.name));
    for (const auto& r : sc.regions)
      if (r.name == ob.name) o.fail("name", fmt::format("'{}' is already a region name", ob.name));
    for (const auto& p : sc.probes)
      if (p.name == ob.name) o.fail("name", fmt::format("'{}' is already a probe name", ob.name));
    for (const auto& q : sc.obstacles)
      if (q.name == ob.name) o.fail("name", fmt::format("duplicate obstacle name '{}'", ob.name));
    const std::string shape = o.string("shape", "sphere", {"sphere", "capsule", "catheter"});
    if (shape == "catheter") {
      o.allow({"diameter_m", "diameter_fr", "motion_m", "push_m"});  // two pairs of alternatives
      // Diameter in metres or in French (1 Fr = 1/3 mm); 6 Fr by default.
      if (o.has("diameter_m") && o.has("diameter_fr"))
        o.fail("diameter_m", "give the diameter as diameter_m or as diameter_fr, not both");
      const double diameter = o.has("diameter_m")
                                  ? o.required_number("diameter_m", 1e-6, 1.0)
                                  : o.number("diameter_fr", 6.0, 0.1, 100.0) * kMetresPerFrench;
      const Vec3 tip = o.required_vec3("tip_m");
      const Vec3 direction = o.required_vec3("direction");
      if (!(direction.norm() > 0.0)) o.fail("direction", "must be a non-zero vector");
      const double length = o.number("length_m", 0.02, 1e-6, 10.0);
      if (length < diameter)
        o.fail("length_m",
               fmt::format("{} m is shorter than the catheter's diameter ({} m)", length, diameter));
      const std::string name = ob.name;
      ob = make_catheter(name, tip, direction, diameter, length);
      // The push: motion_m, or push_m along the catheter's direction.
      if (o.has("motion_m") && o.has("push_m")) o.fail("push_m", "give motion_m or push_m, not both");
      ob.motion_m = o.has("push_m") ? Vec3(o.number("push_m", 0.0, -10.0, 10.0) * direction.normalized())
                                    : o.vec3("motion_m", Vec3::Zero());
    } else {
      ob.shape = shape == "sphere" ? RigidObstacle::Shape::Sphere : RigidObstacle::Shape::Capsule;
      ob.radius_m = o.required_number("radius_m", 1e-12, 1e3);
      if (ob.shape == RigidObstacle::Shape::Capsule)
        o.allow({"a_m", "b_m"});  // neither is the other misspelt
      if (ob.shape == RigidObstacle::Shape::Sphere) {
        ob.a_m = o.required_vec3("centre_m");
      } else {
        ob.a_m = o.required_vec3("a_m");
        ob.b_m = o.required_vec3("b_m");
      }
      ob.tool_point_m = ob.a_m;
      ob.motion_m = o.vec3("motion_m", Vec3::Zero());
    }
    ob.node_radius_m = o.number("node_radius_m", 0.0, 0.0, 1.0);
    o.finish();
    sc.obstacles.push_back(ob);
  }
}

}  // namespace

const char* shape_functions_name(ContactSpec::Shape shape) {
  switch (shape) {
    case ContactSpec::Shape::Quadratic:
      return "quadratic";
    case ContactSpec::Shape::Mls:
      return "mls";
    case ContactSpec::Shape::Interpolated:
      break;
  }
  return "interpolated";
}

namespace {

void read_contact(JsonReader& root, Scene& sc) {
  JsonReader c = root.object("contact");
  // With the accurate wall configuration the tools meet the wall's surface (docs/validation.md: at the nodes
  // its catheter is 3-18 % soft), unless a tool keeps the nodes off itself (node_radius_m), which asks for
  // the nodes. Without tools there is no contact to build.
  bool node_clearance = false;
  for (const RigidObstacle& ob : sc.obstacles) node_clearance = node_clearance || ob.node_radius_m > 0.0;
  const char* surface_default =
      sc.accurate_wall_defaults && !sc.obstacles.empty() && !node_clearance ? "embedded" : "nodes";
  sc.contact.embedded = c.string("surface", surface_default, {"nodes", "embedded"}) == "embedded";
  c.allow({"shape_functions", "stiffness_pa_per_m", "sample_spacing_m"});  // read when present
  if (c.has("shape_functions")) {
    if (!sc.contact.embedded) c.fail("shape_functions", "applies to contact.surface \"embedded\" only");
    const std::string shape =
        c.string("shape_functions", "interpolated", {"interpolated", "quadratic", "mls"});
    sc.contact.shape_functions = shape == "quadratic" ? ContactSpec::Shape::Quadratic
                                 : shape == "mls"     ? ContactSpec::Shape::Mls
                                                      : ContactSpec::Shape::Interpolated;
  }
  if (c.has("stiffness_pa_per_m")) {
    if (!sc.contact.embedded) c.fail("stiffness_pa_per_m", "applies to contact.surface \"embedded\" only");
    sc.contact.stiffness_pa_per_m = c.number("stiffness_pa_per_m", 0.0, 1.0, 1e20);
  }
  if (c.has("sample_spacing_m")) {
    if (!sc.contact.embedded) c.fail("sample_spacing_m", "applies to contact.surface \"embedded\" only");
    sc.contact.sample_spacing_m = c.number("sample_spacing_m", 0.0, 1e-9, 1.0);
  }
  c.finish();
  // node_radius_m turns the default from the wall's surface to the nodes: said unless the scene chose the
  // nodes.
  if (node_clearance && sc.accurate_wall_defaults && !c.has("surface"))
    for (std::size_t o = 0; o < sc.obstacles.size(); ++o)
      if (const RigidObstacle& ob = sc.obstacles[o]; ob.node_radius_m > 0.0)
        sc.warnings.push_back(fmt::format(
            "{}: key 'obstacles.{}.node_radius_m': obstacle '{}' keeps the nodes {:.4g} m off the tool, "
            "which moves "
            "the contact of every tool from the wall's surface (contact.surface \"embedded\", the default of "
            "this "
            "discretisation) to the nodes, where the catheter is 3-18 % soft on the vein "
            "(docs/validation.md), and "
            "presses the wall {:.4g} m deeper than the tool's own surface: remove node_radius_m, or set "
            "contact.surface to \"nodes\" if the nodes' contact is meant",
            root.file(), o, ob.name, ob.node_radius_m, ob.node_radius_m));
  if (sc.contact.embedded)
    for (std::size_t o = 0; o < sc.obstacles.size(); ++o)
      if (sc.obstacles[o].node_radius_m > 0.0)
        root.fail(fmt::format("obstacles.{}.node_radius_m", o),
                  "keeps the nodes off the tool; with contact.surface \"embedded\" the tool meets the wall's "
                  "surface: remove it (or set it to 0)");
}

// Every registered model's block, read by the model's own reader (so `--set other_model.key=...` is checked
// too, and `--set model=...` finds its settings).
void read_model_blocks(JsonReader& root, Scene& sc) {
  // Each block is known before the first is read: "implicit" is not "explicit" misspelt.
  for (const ModelEntry& e : model_registry()) root.allow({e.name.c_str()});
  for (const ModelEntry& e : model_registry()) {
    JsonReader block = root.object(e.name);
    sc.model_settings[e.name] = e.read_settings(block);
  }
}

void read_haptics(JsonReader& root, const std::string& file, Scene& sc) {
  if (root.has("haptics")) {
    JsonReader h = root.object("haptics");
    HapticsSpec& hs = sc.haptics;
    hs.enabled = true;
    hs.tool = h.string("tool", "");
    JsonReader dev = h.object("device");
    dev.string("type", "scripted", {"scripted"});
    const std::filesystem::path traj = dev.required_string("trajectory");
    hs.trajectory = traj.is_relative()
                        ? (std::filesystem::path(file).parent_path() / traj).lexically_normal().string()
                        : traj.string();
    dev.finish();
    hs.mode = h.string("mode", "lockstep", {"lockstep", "realtime"});
    hs.rate_hz = h.number("rate_hz", 1000.0, 1.0, 100000.0);
    hs.ticks_per_step = h.integer("ticks_per_step", 1, 1, 1000);
    hs.duration_s = h.number("duration_s", 0.0, 0.0, 1e5);
    if (hs.duration_s * hs.rate_hz > kMaxSessionTicks)
      h.fail("duration_s",
             fmt::format("{} s at rate_hz = {} Hz is {:.3g} ticks; a session may have at most {:.0e} "
                         "(every tick is kept in memory)",
                         hs.duration_s, hs.rate_hz, hs.duration_s * hs.rate_hz, kMaxSessionTicks));
    hs.force_limit_n = h.number("force_limit_n", 0.88, 1e-6, 100.0);
    hs.force_step_n = h.number("force_step_n", 0.1, 1e-6, 100.0);
    hs.force_scale = h.number("force_scale", 1.0, 0.0, 1e9);
    JsonReader c = h.object("coupling");
    hs.proxy_mass_kg = c.number("proxy_mass_kg", 0.005, 1e-6, 100.0);
    hs.coupling_stiffness_n_per_m = c.number("stiffness_n_per_m", 500.0, 1e-3, 1e6);
    hs.coupling_damping_n_s_per_m = c.number("damping_n_s_per_m", -1.0, -1.0, 1e6);
    c.finish();
    h.finish();
    if (!find_model(sc.model).capabilities.device_driven)
      h.fail("mode",
             fmt::format("a haptic session needs a model a device can drive ({}; model is '{}')",
                         fmt::join(model_names_with(&ModelCapabilities::device_driven), ", "), sc.model));
  }
}

void read_viewer(JsonReader& root, const std::string& file, Scene& sc) {
  JsonReader v = root.object("viewer");
  const std::filesystem::path texture = v.string("texture", "");
  sc.viewer.texture = texture.empty() || texture.is_absolute()
                          ? texture.string()
                          : (std::filesystem::path(file).parent_path() / texture).lexically_normal().string();
  sc.viewer.texture_repeats = v.number("texture_repeats", 1.0, 1e-3, 1e3);
  sc.viewer.force_threshold_n = v.number("force_threshold_n", 0.0, 0.0, 1e6);
  const Vec3 superior = v.vec3("superior", Vec3::UnitZ());
  const Vec3 anterior = v.vec3("anterior", Vec3::UnitY());
  if (!(superior.norm() > 0.0)) v.fail("superior", "must be a non-zero vector");
  sc.viewer.superior = superior.normalized();
  const Vec3 a = anterior - anterior.dot(sc.viewer.superior) * sc.viewer.superior;
  if (!(a.norm() > 1e-6 * anterior.norm()))
    v.fail("anterior", "must be a non-zero vector not parallel to viewer.superior");
  sc.viewer.anterior = a.normalized();
  v.finish();
}

void read_reference(JsonReader& root, Scene& sc) {
  JsonReader ref = root.object("reference");
  sc.reference.type = ref.string("type", "", {"timoshenko_cantilever"});
  if (!sc.reference.type.empty()) {
    if (sc.geometry.type != "beam") ref.fail("type", "timoshenko_cantilever needs geometry.type = \"beam\"");
    sc.reference.region = ref.required_string("region");
    bool found = false;
    for (const auto& r : sc.regions)
      found = found || (r.name == sc.reference.region && r.bc == RegionBcType::Force);
    // A check across blocks: the root's (a misspelt "regions" is named first).
    if (!found) root.fail("reference.region", fmt::format("no force region named '{}'", sc.reference.region));
  }
  ref.finish();
}

void read_mapping_and_output(JsonReader& root, Scene& sc) {
  JsonReader map = root.object("mapping");
  sc.mapping.support_radius_factor =
      map.number("support_radius_factor", MlsMapOptions{}.support_radius_factor, 1.5, 5.0);
  // A map's first radius follows each vertex's nearest node, a layer step away; where a graded lattice is
  // coarse its columns lie up to (coarse spacing / layer step) times farther, so the radius may grow further
  // there (each vertex keeps the smallest radius that passes, so where the lattice is fine nothing changes).
  constexpr int kGradedLatticeGrowths = 12;
  sc.mapping.max_growths = map.integer(
      "max_growths", sc.geometry.refine.enabled ? kGradedLatticeGrowths : MlsMapOptions{}.max_growths, 0, 20);
  map.finish();

  JsonReader out = root.object("output");
  sc.output.vtk = out.boolean("vtk", false);
  sc.output.surface = out.boolean("surface", false);
  sc.output.vtk_every = out.integer("vtk_every", 1, 1, 1000000);
  out.finish();
}

// What the chosen model cannot do, named at the key that asks for it (the registry's capabilities).
void check_model_capabilities(JsonReader& root, Scene& sc) {
  const ModelEntry& model = find_model(sc.model);
  if (!sc.obstacles.empty() && !model.capabilities.takes_tools)
    root.fail("obstacles",
              fmt::format("rigid tools are supported by the models {} (model is '{}')",
                          fmt::join(model_names_with(&ModelCapabilities::takes_tools), ", "), sc.model));
  for (std::size_t r = 0; r < sc.regions.size(); ++r)
    if (std::isfinite(sc.regions[r].release_time_s) && !model.capabilities.releases_regions)
      root.fail(
          fmt::format("regions.{}.bc.release_time_s", r),
          fmt::format("releasing a region is supported by the models {} (model is '{}')",
                      fmt::join(model_names_with(&ModelCapabilities::releases_regions), ", "), sc.model));
  if (sc.contact.embedded && !model.capabilities.embedded_contact)
    root.fail("contact.surface",
              fmt::format("embedded contact is supported by the models {} (model is '{}'); with this "
                          "model the tools meet the nodes: set contact.surface to \"nodes\"",
                          fmt::join(model_names_with(&ModelCapabilities::embedded_contact), ", "), sc.model));
  if (fits_curvature(sc.discretization.basis) && !model.capabilities.quadratic_basis)
    root.fail(
        "discretization.basis",
        fmt::format("the quadratic basis is supported by the models {} (model is '{}', whose constraints "
                    "assume the linear fit)",
                    fmt::join(model_names_with(&ModelCapabilities::quadratic_basis), ", "), sc.model));
  if (sc.energy.stabilizer_fit == StabilizerFit::Quadratic && !model.capabilities.quadratic_basis)
    root.fail(
        "energy.stabilizer_fit",
        fmt::format("the stabiliser on a quadratic fit is supported by the models {} (model is '{}', whose "
                    "constraints assume the linear fit)",
                    fmt::join(model_names_with(&ModelCapabilities::quadratic_basis), ", "), sc.model));
  if (model.law_restriction) {
    const std::string why = model.law_restriction(sc.own_model_settings(), sc.material_law);
    if (!why.empty()) {
      std::vector<std::string> takers;
      for (const ModelEntry& e : model_registry())
        if (!e.law_restriction || e.law_restriction(sc.model_settings.at(e.name), sc.material_law).empty())
          takers.push_back(e.name);
      root.fail("material.law", fmt::format("{} (models that take it: {})", why, fmt::join(takers, ", ")));
    }
  }
}

// Sizes no vessel has, the signature of a scene typed in millimetres: it runs, as a vessel a thousand times
// too large (outer_radius_m 1.5 for the vein: 16 m long, 93 t), and nothing else would say so. The aorta, the
// widest vessel, has a radius of about 12.5 mm.
constexpr double kLargestVesselRadiusM = 0.05;
constexpr double kLongestBodyM = 1.0;

void warn_implausible_sizes(Scene& sc) {
  const GeometrySpec& g = sc.geometry;
  // `typed`: the key's own value, the example of the fix (a centre-line's length comes from its radius of
  // curvature).
  auto warn = [&](const std::string& key, const std::string& what, double value, double limit, double typed) {
    if (!(value > limit)) return;
    sc.warnings.push_back(
        fmt::format("{}: key '{}': {} of {:.4g} m is implausible (above {:g} m); if these are "
                    "millimetres, write them in metres ({:.4g}e-3)",
                    sc.file, key, what, value, limit, typed));
  };
  if (swept_wall(g.type)) {
    const double r = g.tube.outer_radius_m;
    warn("geometry.outer_radius_m", "a vessel radius", r, kLargestVesselRadiusM, r);
  }
  if (g.type == "tube")
    warn("geometry.length_m", "a vessel length", g.tube.length_m, kLongestBodyM, g.tube.length_m);
  if (g.type == "vessel") {
    const CenterlineSpec& c = g.centerline;
    const double length = build_centerline(c).length();
    const std::string key = c.type == "straight"   ? "geometry.centerline.length_m"
                            : c.type == "polyline" ? "geometry.centerline.points_m"
                                                   : "geometry.centerline.radius_of_curvature_m";
    const bool arcs = c.type == "bent" || c.type == "s";
    warn(key, "a centre-line length", length, kLongestBodyM, arcs ? c.radius_of_curvature_m : length);
  }
  if (g.type == "beam") {
    warn("geometry.length_m", "a beam length", g.beam_length_m, kLongestBodyM, g.beam_length_m);
    warn("geometry.width_m", "a beam width", g.beam_width_m, kLongestBodyM, g.beam_width_m);
    warn("geometry.height_m", "a beam height", g.beam_height_m, kLongestBodyM, g.beam_height_m);
  }
  if (g.type == "box") {
    const double side = (g.box.max_m - g.box.min_m).maxCoeff();
    warn("geometry.max_m", "a box side", side, kLongestBodyM, side);
  }
}

// The coarsest node spacing along a wall, in wall thicknesses, at which the forces are measured within a few
// percent (docs/validation.md, "Real-time resolutions"; docs/model/17-limitations.md item 3 says why coarser
// is worse: the supports grow and smooth the strain through the wall):
// - the quadratic fit (quasi_static's default on walls): at 1x the vein (0.3 mm), the aorta (1.5 mm), the
// retina
//   (20 um) and the catheter are within 2.6 % of their fine lattices, the aorta at 1.47x (2.2 mm) is 16.5 %
//   off;
// - the linear fit (implicit's): the real-time aorta at 1.47x is within 3.4 % of its CalculiX reference
// (nothing
//   coarser is measured; issue 44's 1 mm lattice on a 0.5 mm wall, 2x, is 15 % low).
struct WallSpacingLimit {
  double ratio;
  const char* measured;
};

WallSpacingLimit wall_spacing_limit(GradientBasis basis) {
  if (fits_curvature(basis))
    return {
        1.0,
        "with the quadratic fit the vein, the aorta, the retina and the catheter are within 2.6 % of their "
        "fine lattices at 1x, the aorta at 1.47x 16.5 % off"};
  return {1.5, "with the linear fit the real-time aorta at 1.47x is within 3.4 % of its FEM reference"};
}

// The wall's thickness (0: no wall of known thickness).
double wall_thickness_m(const GeometrySpec& g) {
  if (swept_wall(g.type)) return g.tube.wall_thickness_m;
  if (g.type == "mesh") return g.mesh.wall_thickness_m;
  return 0.0;
}

// A lattice too coarse along its wall for its forces (the limit above), and the first fix named when a
// support or surface-map guard fails on it (a guard that fails is how such a lattice usually ends: more
// growths let it run, inaccurately).
void check_wall_spacing(Scene& sc) {
  const GeometrySpec& g = sc.geometry;
  const double t = wall_thickness_m(g);
  if (!(t > 0.0)) return;
  const WallSpacingLimit limit = wall_spacing_limit(sc.discretization.basis);
  const double spacing = g.type == "mesh" ? g.mesh.node_spacing_m : g.tube.node_spacing_m;
  // Some margin over the limit: the bundled real-time lattices sit at exactly 1x.
  const auto coarse = [&](double h) { return h / t > limit.ratio * (1.0 + 1e-9); };
  if (coarse(spacing)) {
    const std::string advice = fmt::format(
        "reduce geometry.node_spacing_m (now {:.2g}x the wall thickness; forces are measured accurate up to "
        "{:g}x)",
        spacing / t, limit.ratio);
    sc.discretization.coarse_spacing_advice = advice;
    sc.mapping.coarse_spacing_advice = advice;
  }
  // On a graded lattice the loads act in its fine window; the spacing away from it is not the forces' (the
  // bundled graded aorta is 4 mm there on a 1.5 mm wall, as close to its reference as the uniform 1 mm
  // lattice).
  const bool graded = g.refine.enabled;
  const double along = graded ? g.refine.node_spacing_m : spacing;
  if (!coarse(along)) return;
  const std::string key = graded ? "geometry.refine.node_spacing_m" : "geometry.node_spacing_m";
  sc.warnings.push_back(
      fmt::format("{}: key '{}': the node spacing along the wall, {:.4g} m, is {:.2g}x the wall "
                  "thickness ({:.4g} m), coarser than the {:g}x up to which the forces are measured "
                  "accurate ({}: docs/validation.md, \"Real-time resolutions\"): reduce {} to at "
                  "most {:.4g} m",
                  sc.file, key, along, along / t, t, limit.ratio, limit.measured, key, limit.ratio * t));
}

}  // namespace

void apply_override(nlohmann::json& doc, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(fmt::format("--set '{}': expected path.to.key=value", assignment));
  const std::string path = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  // JSON if it parses, else a bare word: a string.
  const nlohmann::json value = try_parse_json(text).value_or(nlohmann::json(text));
  if (value.is_string() && !is_valid_utf8(value.get_ref<const std::string&>()))
    throw InputError(fmt::format("--set '{}': the value is not valid UTF-8 text", assignment));
  nlohmann::json* node = &doc;
  std::size_t start = 0;
  while (true) {
    const auto dot = path.find('.', start);
    const std::string part = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw InputError(fmt::format("--set '{}': empty key in the path", assignment));
    nlohmann::json* next = nullptr;
    if (node->is_array()) {
      if (part.find_first_not_of("0123456789") != std::string::npos || part.size() > 9)
        throw InputError(fmt::format("--set '{}': '{}' indexes an array; use a number", assignment, part));
      const std::size_t idx = std::stoul(part);
      if (idx >= node->size())
        throw InputError(fmt::format("--set '{}': index {} is past the end of an array of {}", assignment,
                                     idx, node->size()));
      next = &(*node)[idx];
    } else {
      if (node->is_null()) *node = nlohmann::json::object();
      if (!node->is_object())
        throw InputError(
            fmt::format("--set '{}': '{}' is inside a value that is not an object", assignment, part));
      next = &(*node)[part];
    }
    if (dot == std::string::npos) {
      *next = value;
      return;
    }
    node = next;
    start = dot + 1;
  }
}

Centerline build_centerline(const CenterlineSpec& c) {
  return c.type == "straight" ? straight_centerline(c.length_m)
         : c.type == "bent"   ? bent_centerline(c.radius_of_curvature_m, c.angle_deg, c.leg_length_m)
         : c.type == "s"      ? s_centerline(c.radius_of_curvature_m, c.angle_deg, c.leg_length_m)
                              : Centerline(c.points_m);
}

Scene parse_scene(const nlohmann::json& doc, const std::string& file) {
  Scene sc;
  sc.file = file;
  sc.resolved = doc;
  JsonReader root(doc, "", file);
  sc.name = root.string("name", std::filesystem::path(file).stem().string());
  if (!is_identifier(sc.name, true))
    root.fail(
        "name",
        fmt::format("'{}' is not allowed; use letters, digits, '_' and '-' (it names the output folder)",
                    sc.name));
  sc.description = root.string("description", "");
  sc.model = root.string("model", default_model_name(root.has("haptics")), model_names());
  const std::string formulation = root.string("formulation", "sound", {"sound", "paper_literal"});
  const bool literal = formulation == "paper_literal";
  root.allow({"haptics", "instrument"});  // read when present
  if (!root.has("geometry")) root.missing("geometry", "a geometry object is required");
  sc.geometry = read_geometry(root.object("geometry"));
  read_material(root, sc);
  read_discretization(root, literal, sc);
  read_energy(root, literal, sc);
  read_regions(root, sc);
  align_lattice_to_first_patch(root, sc);
  read_probes(root, sc);
  sc.gravity_m_s2 = root.vec3("gravity_m_s2", Vec3::Zero());
  read_tools(root, sc);
  if (root.has("instrument")) {
    JsonReader block = root.object("instrument");
    sc.instrument = rod::read_instrument(block);
  }
  centre_refinement_on_tool(root, sc);
  read_contact(root, sc);
  read_model_blocks(root, sc);
  read_haptics(root, file, sc);
  read_viewer(root, file, sc);
  read_reference(root, sc);
  read_mapping_and_output(root, sc);
  root.finish();
  check_model_capabilities(root, sc);
  warn_implausible_sizes(sc);
  check_wall_spacing(sc);
  return sc;
}

std::size_t find_tool(const Scene& scene, const std::string& name, const std::string& where) {
  if (scene.obstacles.empty())
    throw InputError(fmt::format("{}: {}: the scene has no tool: add an 'obstacles' entry (e.g. a catheter)",
                                 scene.file, where));
  if (name.empty()) {
    if (scene.obstacles.size() > 1)
      throw InputError(fmt::format("{}: {}: the scene has {} obstacles; name the tool", scene.file, where,
                                   scene.obstacles.size()));
    return 0;
  }
  for (std::size_t o = 0; o < scene.obstacles.size(); ++o)
    if (scene.obstacles[o].name == name) return o;
  throw InputError(fmt::format("{}: {}: no obstacle named '{}'", scene.file, where, name));
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  nlohmann::json doc =
      read_json_file(path, "the scene file", "expected a scene JSON file (docs/scene-format.md)");
  for (const auto& o : overrides) apply_override(doc, o);
  return parse_scene(doc, path);
}

}  // namespace vascsim
