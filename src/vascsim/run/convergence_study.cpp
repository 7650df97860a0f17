#include "vascsim/run/convergence_study.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "vascsim/core/atomic_file.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/run/contact_resolution.hpp"
#include "vascsim/run/runner.hpp"

namespace vascsim {

namespace {

// Two levels match when the nearest node to a tool's tip sits within this many node spacings of the same
// offset from the tool's axis: the measured force moves by up to 8.6 % between a column under the tool and
// half a column off it, and by under 1 % for a quarter of that shift near full depth (docs/validation.md,
// "The tool against the lattice").
constexpr double kToolOffsetTolerance = 0.15;
// ... and when each region's selected extent is the same share of the asked one within this (absolute, in
// selected / asked): a bonded patch's force follows its area; 5 % is half the selection tolerance the region
// report warns at (run/region_report.hpp kSelectionTolerance).
constexpr double kRegionShareTolerance = 0.05;
// A coarser or finer level tries these multiples of its nominal spacing, nearest first, for a lattice that
// matches the scene's (the counts along and around the vessel change by one within about 3 %).
constexpr double kSpacingTrials[] = {1.0, 0.97, 1.03, 0.94, 1.06, 0.91, 1.09};

// The mismatch text of a level whose run was interrupted (core/interrupt.hpp).
constexpr const char* kInterrupted = "interrupted";

class LatticeMismatch : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::string level_name(int index, double spacing_m) {
  return fmt::format("level-{}-{:.4g}mm", index, spacing_m * 1e3);
}

// What a level's run produced, per output point.
struct LevelRecords {
  std::vector<double> load_factor;
  std::vector<bool> converged;
  std::vector<std::vector<double>> values;        // [step][quantity]
  std::vector<std::vector<double>> tool_depth_m;  // [step][tool]
};

// One output of probes.csv: its name, unit and where a step record holds it.
struct Quantity {
  std::string name, unit;
  int tool = -1;  // index into scene.obstacles, for a tool's force
  std::function<double(const StepRecord&)> value;
};

std::vector<Quantity> quantities(const Scene& scene) {
  std::vector<Quantity> q;
  for (std::size_t i = 0; i < scene.regions.size(); ++i) {
    const RegionSpec& r = scene.regions[i];
    switch (r.bc) {
      case RegionBcType::Displacement:
        q.push_back(
            {r.name + " force_n", "N", -1, [i](const StepRecord& s) { return s.regions[i].force_n; }});
        break;
      case RegionBcType::Force:
      case RegionBcType::Probe:
        q.push_back({r.name + " displacement_m", "m", -1,
                     [i](const StepRecord& s) { return s.regions[i].displacement_m; }});
        break;
      case RegionBcType::Fixed:
        break;
    }
  }
  for (std::size_t i = 0; i < scene.probes.size(); ++i)
    q.push_back({scene.probes[i].name + " displacement_m", "m", -1,
                 [i](const StepRecord& s) { return s.probes[i]; }});
  for (std::size_t o = 0; o < scene.obstacles.size(); ++o)
    q.push_back({scene.obstacles[o].name + " force_n", "N", static_cast<int>(o),
                 [o](const StepRecord& s) { return s.obstacles[o].force_n; }});
  return q;
}

// The extent and centre keys a region report compares (run/region_report.cpp): extents as the share of the
// asked one, centres as their offset in units of the asked width.
void add_region_entries(const RegionSelection& sel, LatticeSignature& sig) {
  const nlohmann::json& r = sel.report;
  if (!r.contains("asked") || !r.contains("selected")) return;
  const nlohmann::json &asked = r["asked"], &selected = r["selected"];
  auto number = [](const nlohmann::json& j, const char* key) -> double {
    return j.contains(key) && j[key].is_number() ? j[key].get<double>()
                                                 : std::numeric_limits<double>::quiet_NaN();
  };
  for (const char* key : {"angle_deg", "length_m", "area_m2"}) {
    const double a = number(asked, key), s = number(selected, key);
    if (std::isfinite(a) && std::isfinite(s) && a > 0.0)
      sig.entries.push_back(
          {fmt::format("region '{}': selected {} / asked", sel.name, key), s / a, kRegionShareTolerance});
  }
  for (auto [centre, width] :
       {std::pair{"angle_center_deg", "angle_deg"}, std::pair{"s_center_m", "length_m"}}) {
    const double c = number(asked, centre), s = number(selected, centre), w = number(asked, width);
    if (std::isfinite(c) && std::isfinite(s) && std::isfinite(w) && w > 0.0)
      sig.entries.push_back({fmt::format("region '{}': {} offset / asked {}", sel.name, centre, width),
                             (s - c) / w, kRegionShareTolerance});
  }
}

}  // namespace

std::string LatticeSignature::mismatch(const LatticeSignature& other) const {
  for (const Entry& e : entries)
    for (const Entry& o : other.entries)
      if (e.what == o.what && std::abs(e.value - o.value) > e.tolerance)
        return fmt::format("{}: {:.3f} here, {:.3f} at the scene's spacing (tolerance {:.2f})", e.what,
                           e.value, o.value, e.tolerance);
  return {};
}

LatticeSignature lattice_signature(Simulation& sim) {
  LatticeSignature sig;
  const Body& body = sim.body();
  sig.spacing_m = along_wall_spacing_m(body);
  if (body.wall && body.wall->layer_spacing_m > 0.0)
    sig.wall_layers = static_cast<int>(std::lround(body.wall->thickness_m / body.wall->layer_spacing_m)) + 1;
  const Vec3Array& X = body.cloud.positions;
  for (const RigidObstacle& tool : sim.scene().obstacles) {
    Vec3 axis = tool.motion_m.norm() > 0.0 ? Vec3(tool.motion_m) : Vec3(tool.b_m - tool.a_m);
    if (!(axis.norm() > 0.0) || X.empty()) continue;
    axis.normalize();
    const Vec3 tip = tool.tool_point_m;
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < X.size(); ++i)
      if ((X[i] - tip).squaredNorm() < (X[nearest] - tip).squaredNorm()) nearest = i;
    const Vec3 d = X[nearest] - tip;
    const double off_axis = (d - d.dot(axis) * axis).norm();
    sig.entries.push_back(
        {fmt::format("tool '{}': nearest node's offset from its axis, in node spacings", tool.name),
         off_axis / sig.spacing_m, kToolOffsetTolerance});
  }
  for (const RegionSelection& sel : sim.region_selections()) add_region_entries(sel, sig);
  return sig;
}

Scene scene_at_spacing(const Scene& scene, double factor) {
  nlohmann::json doc = scene.resolved;
  nlohmann::json& geometry = doc["geometry"];
  if (!geometry.contains("node_spacing_m") || !geometry["node_spacing_m"].is_number())
    throw InputError(
        fmt::format("{}: 'geometry.node_spacing_m' is not set; a convergence study varies it", scene.file));
  geometry["node_spacing_m"] = geometry["node_spacing_m"].get<double>() * factor;
  if (geometry.contains("refine") && geometry["refine"].is_object() &&
      geometry["refine"].contains("node_spacing_m"))
    geometry["refine"]["node_spacing_m"] = geometry["refine"]["node_spacing_m"].get<double>() * factor;
  doc["output"]["vtk"] = false;
  doc["output"]["surface"] = false;
  return parse_scene(doc, scene.file);
}

nlohmann::json ConvergenceResult::to_json() const {
  nlohmann::json j;
  j["levels"] = nlohmann::json::array();
  for (const ConvergenceLevel& l : levels) {
    nlohmann::json sig = nlohmann::json::object();
    for (const auto& e : l.signature.entries) sig[e.what] = e.value;
    j["levels"].push_back({{"factor", l.factor},
                           {"spacing_m", l.spacing_m},
                           {"nodes", l.nodes},
                           {"wall_layers", l.signature.wall_layers},
                           {"seconds", l.seconds},
                           {"scene_resolution", l.user},
                           {"out_dir", l.out_dir.string()},
                           {"lattice", sig},
                           {"factors_tried_first", l.tried_factors}});
  }
  j["user_level"] = user_level;
  j["refused"] = refused;
  j["outputs"] = nlohmann::json::array();
  for (const ConvergenceOutput& o : outputs) {
    nlohmann::json row = {{"quantity", o.quantity},       {"unit", o.unit},     {"step", o.step},
                          {"load_factor", o.load_factor}, {"values", o.values}, {"status", o.status}};
    if (o.tool_displacement_m >= 0.0) row["tool_displacement_m"] = o.tool_displacement_m;
    if (o.status == "extrapolated") {
      row["observed_order"] = o.estimate.order;
      row["extrapolated"] = o.estimate.extrapolated;
      row["error"] = o.user_error;
      row["error_bound"] = o.user_bound;
    }
    if (o.has_check) row["check_order"] = o.check_order;
    j["outputs"].push_back(row);
  }
  return j;
}

namespace {

// Runs one level: the first spacing of the trials whose lattice matches `reference` (the scene's own level
// has no reference and one trial). Empty out_dir in the result when none matched.
ConvergenceLevel run_level(const Scene& scene, const ConvergenceOptions& options,
                           const std::vector<Quantity>& quantities, double nominal, int index,
                           const LatticeSignature* reference, LevelRecords& records, std::string& mismatch) {
  ConvergenceLevel level;
  level.user = reference == nullptr;
  const std::vector<double> trials =
      level.user ? std::vector<double>{1.0}
                 : std::vector<double>(std::begin(kSpacingTrials), std::end(kSpacingTrials));
  const double scene_spacing = scene.resolved["geometry"]["node_spacing_m"].get<double>();
  for (double trial : trials) {
    const double factor = nominal * trial;
    const Scene level_scene = scene_at_spacing(scene, factor);
    RunOptions run;
    run.out_dir = options.out_dir / level_name(index, scene_spacing * factor);
    run.checks = options.checks;
    LevelRecords got;
    run.after_setup = [&](Simulation& sim) {
      level.signature = lattice_signature(sim);
      level.nodes = static_cast<int>(sim.body().cloud.positions.size());
      if (reference) {
        const std::string m = level.signature.mismatch(*reference);
        if (!m.empty()) throw LatticeMismatch(m);
      }
    };
    run.on_step = [&](const StepRecord& r, int total) {
      got.load_factor.push_back(r.report.load_factor);
      got.converged.push_back(r.report.converged);
      std::vector<double> values;
      for (const Quantity& q : quantities) values.push_back(q.value(r));
      got.values.push_back(std::move(values));
      std::vector<double> depth;
      for (const ObstacleMeasure& m : r.obstacles) depth.push_back(m.displacement_m);
      got.tool_depth_m.push_back(depth);
      if (options.on_step) options.on_step(r, total);
    };
    Stopwatch clock;
    try {
      const nlohmann::json summary = run_scene(level_scene, run);
      if (summary.value("interrupted", false)) {
        mismatch = kInterrupted;
        return level;
      }
    } catch (const LatticeMismatch& e) {
      spdlog::info("converge: spacing x{:.3f}: the lattice differs ({}); next trial", factor, e.what());
      std::error_code ec;
      std::filesystem::remove_all(run.out_dir, ec);
      level.tried_factors.push_back(factor);
      mismatch = e.what();
      continue;
    }
    level.seconds = clock.seconds();
    level.factor = factor;
    level.spacing_m = level.signature.spacing_m;
    level.out_dir = run.out_dir;
    records = std::move(got);
    mismatch.clear();
    return level;
  }
  return level;
}

std::string format_csv(const ConvergenceResult& result) {
  std::string s =
      "quantity,unit,step,load_factor,tool_displacement_m,status,observed_order,extrapolated,error,"
      "error_bound";
  for (const ConvergenceLevel& l : result.levels) s += fmt::format(",value_h{:.6g}", l.spacing_m);
  s += "\n";
  for (const ConvergenceOutput& o : result.outputs) {
    const bool e = o.status == "extrapolated";
    s += fmt::format("{},{},{},{:.9g},{},{},{},{},{},{}", o.quantity, o.unit, o.step, o.load_factor,
                     o.tool_displacement_m >= 0.0 ? fmt::format("{:.9g}", o.tool_displacement_m) : "",
                     o.status, e ? fmt::format("{:.4f}", o.estimate.order) : "",
                     e ? fmt::format("{:.9g}", o.estimate.extrapolated) : "",
                     e ? fmt::format("{:.6g}", o.user_error) : "",
                     e ? fmt::format("{:.6g}", o.user_bound) : "");
    for (double v : o.values) s += fmt::format(",{:.9g}", v);
    s += "\n";
  }
  return s;
}

void estimate(const Scene& scene, const Quantity& q, const std::vector<ConvergenceLevel>& levels, int user,
              const std::vector<const LevelRecords*>& records, int step, ConvergenceOutput& out) {
  const std::size_t n = levels.size();
  for (std::size_t k = 0; k < n; ++k)
    if (!records[k]->converged[step]) {
      out.status = "not converged";
      return;
    }
  double largest = 0.0;
  for (double v : out.values) largest = std::max(largest, std::abs(v));
  if (largest == 0.0) {
    out.status = "zero";
    return;
  }
  if (q.tool >= 0) {
    const RigidObstacle& tool = scene.obstacles[static_cast<std::size_t>(q.tool)];
    for (std::size_t k = 0; k < n; ++k) {
      const double d =
          hertz_contact_diameter_m(std::abs(out.values[k]), tool.radius_m, scene.material.youngs_modulus_pa,
                                   scene.material.poisson_ratio);
      if (d < kResolvedContactSpacings * levels[k].spacing_m) {
        out.status = "contact not resolved";
        return;
      }
    }
  }
  const double h[3] = {levels[0].spacing_m, levels[1].spacing_m, levels[2].spacing_m};
  const double f[3] = {out.values[0], out.values[1], out.values[2]};
  out.estimate = richardson_extrapolate(h, f);
  out.status = richardson_status_name(out.estimate.status);
  if (n >= 4) {
    const double hc[3] = {levels[1].spacing_m, levels[2].spacing_m, levels[3].spacing_m};
    const double fc[3] = {out.values[1], out.values[2], out.values[3]};
    const Richardson check = richardson_extrapolate(hc, fc);
    out.has_check = true;
    out.check_order = check.order;
    // Two estimates of the order that differ by more than half the larger: the sequence is not in the
    // asymptotic range, whatever the three finest say.
    if (out.estimate.status == RichardsonStatus::Extrapolated &&
        (check.status != RichardsonStatus::Extrapolated ||
         std::abs(check.order - out.estimate.order) > 0.5 * std::max(check.order, out.estimate.order)))
      out.status = "orders disagree";
  }
  if (out.status != "extrapolated") return;
  out.user_error = relative_error(out.values[static_cast<std::size_t>(user)], out.estimate.extrapolated);
  out.user_bound = user == 0 ? out.estimate.fine_gci : kGciSafetyFactor * std::abs(out.user_error);
}

}  // namespace

ConvergenceResult run_convergence_study(const Scene& scene, const ConvergenceOptions& options) {
  if (scene.haptics.enabled)
    throw InputError(
        fmt::format("{}: a convergence study runs load steps headless; this scene is a haptic session "
                    "('haptics' block): remove the block, or study its headless sibling scene",
                    scene.file));
  if (!(options.ratio > 1.0) || options.ratio > 4.0)
    throw InputError(
        fmt::format("--ratio {}: the spacing ratio between levels must be in (1, 4]", options.ratio));
  const int coarser = options.coarser_levels;
  if (coarser < 1 || (coarser < 2 && !options.finer))
    throw InputError(
        "a convergence study needs three resolutions: two coarser levels, or one coarser and --finer");
  (void)scene_at_spacing(scene, 1.0);  // a scene without a node spacing fails here, before any run

  // Run order: the scene's own level (the others must match its lattice), the coarser ones, then the finer
  // one.
  struct Planned {
    double nominal;
    int fine_to_coarse;
  };
  std::vector<Planned> plan;
  const int user = options.finer ? 1 : 0;
  plan.push_back({1.0, user});
  for (int k = 1; k <= coarser; ++k) plan.push_back({std::pow(options.ratio, k), user + k});
  if (options.finer) plan.push_back({1.0 / options.ratio, 0});
  const int n = static_cast<int>(plan.size());

  ConvergenceResult result;
  result.user_level = user;
  result.levels.resize(static_cast<std::size_t>(n));
  std::vector<LevelRecords> records(static_cast<std::size_t>(n));
  std::filesystem::create_directories(options.out_dir);
  const std::vector<Quantity> qs = quantities(scene);
  auto write = [&] {
    write_file_atomically(options.out_dir / "convergence.json", result.to_json().dump(2) + "\n");
    write_file_atomically(options.out_dir / "convergence.csv", format_csv(result));
  };
  for (int r = 0; r < n; ++r) {
    const Planned& p = plan[static_cast<std::size_t>(r)];
    if (options.on_level)
      options.on_level(
          r, n, p.nominal,
          p.nominal == 1.0 ? std::string("the scene's spacing") : fmt::format("spacing x{:.3f}", p.nominal));
    const LatticeSignature* reference =
        r == 0 ? nullptr : &result.levels[static_cast<std::size_t>(user)].signature;
    std::string mismatch;
    ConvergenceLevel level = run_level(scene, options, qs, p.nominal, p.fine_to_coarse, reference,
                                       records[static_cast<std::size_t>(p.fine_to_coarse)], mismatch);
    if (level.out_dir.empty() && mismatch == kInterrupted) {
      result.levels.resize(0);
      result.refused = "interrupted before every level ran: no estimate";
      write();
      return result;
    }
    if (level.out_dir.empty()) {
      result.levels.resize(0);
      result.refused = fmt::format(
          "no spacing within {:.0f} % of {:.3f} times the scene's gives the lattice the scene's spacing has "
          "under its "
          "tools and regions ({}); across lattices that differ there the force changes with where the nodes "
          "fall, not "
          "with the resolution, and no extrapolation is made. Try another --ratio, or a scene whose regions "
          "the "
          "lattice fits (geometry.fit_lattice_to_patch)",
          100.0 * (kSpacingTrials[std::size(kSpacingTrials) - 1] - 1.0), p.nominal, mismatch);
      write();
      return result;
    }
    result.levels[static_cast<std::size_t>(p.fine_to_coarse)] = std::move(level);
  }

  std::size_t steps = records[0].values.size();
  for (const LevelRecords& rec : records) steps = std::min(steps, rec.values.size());
  std::vector<const LevelRecords*> ptrs;
  for (const LevelRecords& rec : records) ptrs.push_back(&rec);
  const LevelRecords& mine = records[static_cast<std::size_t>(user)];
  for (std::size_t s = 1; s < steps; ++s)  // step 0 is the rest state
    for (std::size_t q = 0; q < qs.size(); ++q) {
      ConvergenceOutput out;
      out.quantity = qs[q].name;
      out.unit = qs[q].unit;
      out.step = static_cast<int>(s);
      out.load_factor = mine.load_factor[s];
      if (qs[q].tool >= 0)
        out.tool_displacement_m = mine.tool_depth_m[s][static_cast<std::size_t>(qs[q].tool)];
      for (const LevelRecords& rec : records) out.values.push_back(rec.values[s][q]);
      estimate(scene, qs[q], result.levels, user, ptrs, static_cast<int>(s), out);
      result.outputs.push_back(std::move(out));
    }
  write();
  return result;
}

double spacing_for_target(const ConvergenceResult& result, const ConvergenceOutput& output, double target) {
  if (output.status != "extrapolated" || output.user_error == 0.0 || !(target > 0.0)) return 0.0;
  return resolution_for_error(result.levels[static_cast<std::size_t>(result.user_level)].spacing_m,
                              output.user_error, output.estimate.order, target);
}

}  // namespace vascsim
