// Material laws in scenes (issue 6): the material block chooses the law; quasi_static and explicit run
// any law through the point-primitive assembly; bad blocks fail naming the key. The laws themselves are
// tested in test_hyperelastic_laws.cpp and their assembly (forces = -grad U, Hessian products) in
// test_energy_consistency.cpp.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "vascsim/app/cli.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

using json = nlohmann::json;

// A 4 mm cube, base fixed, the top pulled up by a force.
json cube(double force_n) {
  json doc = json::parse(R"({
    "name": "law-cube", "model": "quasi_static",
    "geometry": { "type": "box", "min_m": [0, 0, 0], "max_m": [0.004, 0.004, 0.004], "node_spacing_m": 0.001 },
    "material": { "youngs_modulus_pa": 5e5, "poisson_ratio": 0.45 },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } },
                 { "name": "top", "select": { "type": "box", "min_m": [-1, -1, 0.004] },
                   "bc": { "type": "force", "direction": [0, 0, 1], "magnitude_n": 0 } } ],
    "quasi_static": { "load_steps": 1, "rel_tolerance": 1e-8 }
  })");
  doc["regions"][1]["bc"]["magnitude_n"] = force_n;
  return doc;
}

double top_displacement(const json& doc) {
  Simulation sim(parse_scene(doc, "law-cube"));
  StepRecord rec;
  for (int k = 1; k <= sim.model().num_steps(); ++k) rec = sim.advance(k);
  EXPECT_TRUE(rec.report.converged);
  return rec.regions.at(1).displacement_m;
}

void expect_input_error(const json& doc, const std::string& needle) {
  try {
    Simulation sim(parse_scene(doc, "law-cube"));
    ADD_FAILURE() << "no error; expected one mentioning " << needle;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

// The laws share the linearisation of E, nu: at a strain of ~1e-5 the stretch of the top agrees with svk
// to 0.5 % (the issue's small-strain bound; the nonlinear terms are ~1e-5 relative).
TEST(MaterialLawScene, AllLawsMatchSvkAtSmallStrain) {
  const json svk = cube(1e-4);
  const double u_svk = top_displacement(svk);
  ASSERT_GT(u_svk, 0.0);
  json neo = svk;
  neo["material"]["law"] = "neo_hookean";
  EXPECT_NEAR(top_displacement(neo) / u_svk, 1.0, 5e-3);
  // Mooney-Rivlin with mu = 2 (C10 + C01) and the bulk modulus of E = 0.5 MPa, nu = 0.45.
  const double mu = 5e5 / (2 * 1.45), kappa = 5e5 / (3 * (1 - 0.9));
  json mr = svk;
  mr["material"] = {
      {"law", "mooney_rivlin"}, {"c10_pa", 0.35 * mu}, {"c01_pa", 0.15 * mu}, {"bulk_modulus_pa", kappa}};
  EXPECT_NEAR(top_displacement(mr) / u_svk, 1.0, 5e-3);
}

// Large stretch (about 30 %): the laws part ways (neo-Hookean stiffens less than SVK in tension), so the
// small-strain agreement above is not an artefact of a shared code path.
TEST(MaterialLawScene, LawsDifferAtLargeStrain) {
  json svk = cube(2.0);
  svk["quasi_static"]["load_steps"] = 4;
  json neo = svk;
  neo["material"]["law"] = "neo_hookean";
  const double u_svk = top_displacement(svk), u_neo = top_displacement(neo);
  std::printf("[ laws     ] cube pulled by 2 N: top displacement svk %.4g mm, neo-Hookean %.4g mm\n",
              u_svk * 1e3, u_neo * 1e3);
  EXPECT_GT(u_svk, 0.5e-3);  // a large strain indeed (> 12 %)
  EXPECT_GT(std::abs(u_neo / u_svk - 1.0), 0.02);
}

// hgo on a tube: with k1 = 0 it is its neo-Hookean ground matrix (same energy, so the same answer to the
// solver tolerance); with collagen fibres (k1 > 0) an axially pulled tube stretches less. The fibres are at
// 70 deg from the circumferential direction (near the adventitia's 62 deg): an axial strain e stretches them
// by about (sin^2 70 - nu cos^2 70) e = 0.83 e. At the media's 29 deg the same pull shortens them
// ((sin^2 29 - 0.45 cos^2 29) e < 0), and they stay slack.
TEST(MaterialLawScene, HgoFibresStiffenATubeInTension) {
  json doc = json::parse(R"({
    "name": "hgo-tube", "model": "quasi_static",
    "geometry": { "type": "tube", "outer_radius_m": 0.003, "wall_thickness_m": 0.0006, "length_m": 0.003,
                  "node_spacing_m": 0.0003, "min_layers": 3 },
    "material": { "law": "hgo", "shear_modulus_pa": 3e4, "bulk_modulus_pa": 2.9e5, "k1_pa": 0, "k2": 0.8393,
                  "fibre_angle_deg": 70 },
    "regions": [ { "name": "start", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } },
                 { "name": "pull", "select": { "type": "cylinder_end", "end": "end" },
                   "bc": { "type": "force", "direction": [0, 0, 1], "magnitude_n": 0.02 } } ],
    "quasi_static": { "load_steps": 2, "rel_tolerance": 1e-9 }
  })");
  auto stretch = [](const json& d) {
    Simulation sim(parse_scene(d, "hgo-tube"));
    StepRecord rec;
    for (int k = 1; k <= sim.model().num_steps(); ++k) rec = sim.advance(k);
    EXPECT_TRUE(rec.report.converged);
    return rec.regions.at(1).displacement_m;
  };
  const double u_ground = stretch(doc);
  json neo = doc;
  const double mu = 3e4, kappa = 2.9e5;
  neo["material"] = {{"law", "neo_hookean"},
                     {"youngs_modulus_pa", 9 * kappa * mu / (3 * kappa + mu)},
                     {"poisson_ratio", (3 * kappa - 2 * mu) / (2 * (3 * kappa + mu))}};
  EXPECT_NEAR(stretch(neo) / u_ground, 1.0, 1e-6);
  json fibres = doc;
  fibres["material"]["k1_pa"] = 2.3632e4;
  const double u_fibres = stretch(fibres);
  std::printf("[ laws     ] hgo tube pulled by 20 mN: %.4g mm slack fibres, %.4g mm with k1 = 23.6 kPa\n",
              u_ground * 1e3, u_fibres * 1e3);
  EXPECT_LT(u_fibres, 0.9 * u_ground);
  EXPECT_GT(u_fibres, 0.0);
}

// xpbd with a law: one scalar energy constraint per node (xpbd_model.cpp). On a small stiff-enough cube at
// small strain and many sweeps, its steady state approaches the quasi_static equilibrium of the same law,
// as the SVK block does (docs/validation.md: within 1-2 % on the cantilever at 16-32 sweeps per step).
TEST(MaterialLawScene, XpbdWithALawApproachesTheStaticSolution) {
  json doc = cube(2e-3);
  doc["material"]["law"] = "neo_hookean";
  doc["material"]["youngs_modulus_pa"] = 2e4;
  const double u_static = top_displacement(doc);
  doc["model"] = "xpbd";
  doc["xpbd"] = {{"duration_s", 0.6},   {"ramp_time_s", 0.1}, {"output_interval_s", 0.1},
                 {"damping_per_s", 30}, {"substeps", 8},      {"iterations", 4}};
  Simulation sim(parse_scene(doc, "law-cube"));
  StepRecord rec, previous;
  for (int k = 1; k <= sim.model().num_steps(); ++k) {
    previous = rec;
    rec = sim.advance(k);
  }
  const double u_xpbd = rec.regions.at(1).displacement_m;
  std::printf("[ laws     ] neo-Hookean cube: quasi_static %.5g mm, xpbd 8x4 steady %.5g mm (%.2f %%)\n",
              u_static * 1e3, u_xpbd * 1e3, 100 * (u_xpbd / u_static - 1));
  EXPECT_NEAR(rec.regions.at(1).displacement_m, previous.regions.at(1).displacement_m,
              1e-3 * u_static);  // steady
  EXPECT_NEAR(u_xpbd / u_static, 1.0, 0.05);
}

TEST(MaterialLawScene, BadMaterialBlocksNameTheKey) {
  json d = cube(1e-3);
  d["material"]["law"] = "ogden";
  EXPECT_THROW(parse_scene(d, "law-cube"), InputError);
  d = cube(1e-3);
  d["material"] = {{"law", "mooney_rivlin"}, {"c10_pa", 1e4}, {"bulk_modulus_pa", 1e6}};
  expect_input_error(d, "c01_pa");
  d["material"]["c01_pa"] = 1e4;
  d["material"]["youngs_modulus_pa"] = 5e5;  // not a Mooney-Rivlin parameter
  expect_input_error(d, "youngs_modulus_pa");
  d = cube(1e-3);
  d["material"]["law"] = "neo_hookean";
  d["material"]["poisson_ratio"] = 0.5;
  expect_input_error(d, "poisson_ratio");
  d["material"]["poisson_ratio"] = 0.45;
  d["model"] = "paper_literal";
  expect_input_error(d, "material.law");
  d["model"] = "xpbd";
  d["xpbd"] = {{"elastic", "tet_neo_hookean"}};
  expect_input_error(d, "material.law");
  d = cube(1e-3);
  d["material"] = {{"law", "hgo"}, {"shear_modulus_pa", 3e4}, {"bulk_modulus_pa", 3e5}, {"k1_pa", 2e4},
                   {"k2", 0.8},    {"fibre_angle_deg", 29}};
  expect_input_error(d, "centre-line");  // a box has no vessel frame for the fibres
  d["material"]["fibre_angle_deg"] = 95;
  expect_input_error(d, "fibre_angle_deg");
  d["material"]["fibre_angle_deg"] = 29;
  d["material"]["k2"] = -1;
  expect_input_error(d, "k2");
}

TEST(MaterialLawScene, BadMaterialExitsWithCode2) {
  std::ostringstream out, err;
  EXPECT_EQ(run_cli({"run", std::string(VASCSIM_SOURCE_DIR) + "/scenes/vein-indent.json", "--set",
                     "material.law=neo_hookean", "--set", "material.poisson_ratio=0.5", "--out",
                     "/tmp/vascsim-bad-law"},
                    out, err),
            2);
  EXPECT_NE(err.str().find("poisson_ratio"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace vascsim
