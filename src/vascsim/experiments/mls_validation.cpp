#include "vascsim/experiments/mls_validation.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <chrono>

#include "vascsim/core/error.hpp"
#include "vascsim/core/spatial_grid.hpp"
#include "vascsim/mapping/mls_checks.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

nlohmann::json validate_mls(const std::vector<std::string>& scene_files,
                            const std::vector<std::string>& overrides, double tight_factor) {
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string& file : scene_files) {
    const Scene scene = load_scene(file, overrides);
    const Body body = build_body(scene.geometry);
    if (!body.surface)
      throw InputError(fmt::format("{}: geometry '{}' has no render surface", file, scene.geometry.type));
    const Vec3Array& X = body.cloud.positions;
    const double delta = mean_nearest_spacing(X);
    const auto t0 = std::chrono::steady_clock::now();
    const MlsMap map(X, body.surface->rest_vertices, scene.mapping);
    const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const MlsT11 m = measure_mls_t11(map, X, delta, 2021);
    const MlsMapReport& r = map.report();
    nlohmann::json row = {{"scene", scene.name},
                          {"file", file},
                          {"geometry", scene.geometry.type},
                          {"nodes", X.size()},
                          {"vertices", map.num_vertices()},
                          {"mean_spacing_m", delta},
                          {"support_radius_factor", scene.mapping.support_radius_factor},
                          {"unity", m.unity},
                          {"linear_over_delta", m.linear},
                          {"affine_over_delta", m.affine},
                          {"rigid90_over_delta", m.rigid90},
                          {"rigid_random_over_delta", m.rigid_rand},
                          {"f32_over_delta", m.f32},
                          {"max_displacement_over_delta", m.max_displacement},
                          {"f32_over_input_rounding", m.f32_over_input_rounding},
                          {"max_cond", m.max_cond},
                          {"min_support", r.min_support},
                          {"mean_support", r.mean_support},
                          {"max_support", r.max_support},
                          {"grown_vertices", r.grown_vertices},
                          {"build_s", build_s},
                          {"t11_pass", m.passes()}};
    // T15: a support radius too small for the cloud must grow or fail loudly.
    MlsMapOptions tight = scene.mapping;
    tight.support_radius_factor = tight_factor;
    nlohmann::json guard = {{"support_radius_factor", tight_factor}};
    try {
      const MlsMap small(X, body.surface->rest_vertices, tight);
      const MlsT11 ms = measure_mls_t11(small, X, delta, 2021);
      guard["outcome"] = "grown";
      guard["grown_vertices"] = small.report().grown_vertices;
      guard["max_cond"] = ms.max_cond;
      guard["min_support"] = small.report().min_support;
      guard["t11_pass"] = ms.passes();
    } catch (const NumericalError& e) {
      guard["outcome"] = "failed loudly";
      guard["message"] = e.what();
    }
    row["t15"] = guard;
    spdlog::info("{}: T11 {}, T15 at factor {}: {}", scene.name, m.passes() ? "pass" : "FAIL", tight_factor,
                 guard["outcome"].get<std::string>());
    rows.push_back(row);
  }
  return rows;
}

std::string mls_validation_table(const nlohmann::json& rows) {
  std::string s =
      "| scene | nodes | vertices | max abs(sum phi - 1) | linear / Delta | affine / Delta | rigid / Delta | "
      "float32 / "
      "Delta (/ eps max abs(u)) | max cond | abs(S) min / mean | grown | T11 | T15 (tight r) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    const auto& g = r["t15"];
    const std::string t15 =
        g["outcome"] == "grown"
            ? fmt::format("{:.2f} Delta: {} grown, cond {:.3g}, T11 {}",
                          g["support_radius_factor"].get<double>(), g["grown_vertices"].get<long>(),
                          g["max_cond"].get<double>(), g["t11_pass"].get<bool>() ? "pass" : "fail")
            : fmt::format("{:.2f} Delta: fails loudly", g["support_radius_factor"].get<double>());
    s += fmt::format(
        "| {} | {} | {} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {:.1e} ({:.2f}) | {:.3g} | {} / {:.1f} | {} | "
        "{} | {} |\n",
        r["scene"].get<std::string>(), r["nodes"].get<long>(), r["vertices"].get<long>(),
        r["unity"].get<double>(), r["linear_over_delta"].get<double>(), r["affine_over_delta"].get<double>(),
        std::max(r["rigid90_over_delta"].get<double>(), r["rigid_random_over_delta"].get<double>()),
        r["f32_over_delta"].get<double>(), r["f32_over_input_rounding"].get<double>(),
        r["max_cond"].get<double>(), r["min_support"].get<long>(), r["mean_support"].get<double>(),
        r["grown_vertices"].get<long>(), r["t11_pass"].get<bool>() ? "pass" : "FAIL", t15);
  }
  return s;
}

}  // namespace vascsim
