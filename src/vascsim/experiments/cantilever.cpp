#include "vascsim/experiments/cantilever.hpp"

#include <chrono>

#include "vascsim/core/beam_theory.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

namespace {
constexpr double kWidth = 0.01;    // b, m
constexpr double kLength = 0.1;    // L = 10 b, m
constexpr double kYoungs = 1.0e6;  // E, Pa
}  // namespace

nlohmann::json cantilever_scene(const CantileverCase& c) {
  const double delta = kWidth / c.cells_across;
  // Load giving delta_T = deflection_fraction * L.
  const double unit = timoshenko_tip_deflection(1.0, kLength, kWidth, kWidth, kYoungs, c.poisson_ratio);
  const double load = c.deflection_fraction * kLength / unit;
  return {
      {"name", "cantilever"},
      {"model", "quasi_static"},
      {"geometry",
       {{"type", "beam"},
        {"length_m", kLength},
        {"width_m", kWidth},
        {"height_m", kWidth},
        {"node_spacing_m", delta},
        {"clamp_layers", 3}}},
      {"material",
       {{"youngs_modulus_pa", kYoungs}, {"poisson_ratio", c.poisson_ratio}, {"density_kg_m3", 1060.0}}},
      {"discretization",
       {{"support_radius_factor", c.support_radius_factor},
        {"min_neighbours", c.min_neighbours},
        {"volume", c.volume}}},
      {"energy",
       {{"strain", c.strain},
        {"stabilizer_alpha", c.stabilizer_alpha},
        {"stabilizer_fit", c.stabilizer_fit}}},
      {"regions",
       {{{"name", "clamp"},
         {"select", {{"type", "box"}, {"max_m", {1e-9, 1.0, 1.0}}, {"min_m", {-1.0, -1.0, -1.0}}}},
         {"bc", {{"type", "fixed"}}}},
        {{"name", "tip"},
         {"select", {{"type", "box"}, {"min_m", {kLength - 1e-9, -1.0, -1.0}}, {"max_m", {1.0, 1.0, 1.0}}}},
         {"bc", {{"type", "force"}, {"direction", {0.0, 0.0, -1.0}}, {"magnitude_n", load}}}}}},
      {"quasi_static", {{"load_steps", 1}, {"rel_tolerance", 1e-8}}},
      {"reference", {{"type", "timoshenko_cantilever"}, {"region", "tip"}}}};
}

std::vector<CantileverConfiguration> cantilever_table_configurations() {
  const CantileverCase sound;
  auto with = [&](auto change) {
    CantileverCase c = sound;
    change(c);
    return c;
  };
  return {
      {"sound, nu = 0.3", with([](auto& c) { c.poisson_ratio = 0.3; })},
      {"sound, nu = 0.45", sound},
      {"sound, K_min = 4 (no support growth at edges), nu = 0.3", with([](auto& c) {
         c.poisson_ratio = 0.3;
         c.min_neighbours = 4;
       })},
      {"sound, K_min = 4 (no support growth at edges), nu = 0.45",
       with([](auto& c) { c.min_neighbours = 4; })},
      {"sound without stabiliser (alpha_hg = 0), nu = 0.45", with([](auto& c) { c.stabilizer_alpha = 0.0; })},
      {"stabiliser on the quadratic fit's residuals, nu = 0.45",
       with([](auto& c) { c.stabilizer_fit = "quadratic"; })},
      {"h = 1.5 Delta, nu = 0.45", with([](auto& c) { c.support_radius_factor = 1.5; })},
      {"alpha_hg = 0.5, nu = 0.45", with([](auto& c) { c.stabilizer_alpha = 0.5; })},
      {"Mueller-kernel volumes, nu = 0.45", with([](auto& c) { c.volume = "mueller_kernel"; })},
      {"literal strain (no 1/2), alpha_hg = 0, nu = 0.45", with([](auto& c) {
         c.strain = "mueller_no_half";
         c.stabilizer_alpha = 0.0;
       })}};
}

CantileverResult run_cantilever(const CantileverCase& c) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene scene = parse_scene(cantilever_scene(c), "cantilever (generated)");
  Simulation sim(scene);
  const StepRecord rec = sim.advance(1);
  const nlohmann::json ref = sim.reference(rec);
  CantileverResult r;
  r.tip_deflection_m = ref["tip_deflection_m"];
  r.reference_m = ref["reference_deflection_m"];
  r.ratio = ref["ratio"];
  r.nodes = sim.discretization().num_nodes();
  r.newton_iterations = rec.report.iterations;
  r.residual = rec.report.residual;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace vascsim
