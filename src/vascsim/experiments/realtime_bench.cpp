#include "vascsim/experiments/realtime_bench.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <thread>

#include "vascsim/core/error.hpp"
#include "vascsim/core/statistics.hpp"
#include "vascsim/experiments/machine_info.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/simulation.hpp"

namespace vascsim {

namespace {

constexpr double kHapticMaxMs = 1.0;
constexpr int kHapticMinNodes = 2000;
constexpr double kVisualMinStepsPerS = 85.0;
constexpr int kVisualMinNodes = 20000;
constexpr int kTargetMaxThreads = 2;  // both targets are stated "on 2 cores"
// Below ~5k nodes the vein's wall layers (0.15 mm apart) are much closer than the spacing along the tube,
// so the meshless neighbourhoods need more than the default 3 growths of the support radius to be
// well-conditioned (a 1k-node vein fails otherwise). xpbd steps on the tets alone, so this changes the
// set-up, not the timed step; only nodes that fail the guard grow.
constexpr const char* kBenchDefaultOverride = "discretization.max_growths=10";
// make_tube refuses 5e7 nodes; bracketing may overshoot a target by up to ~2x.
constexpr int kMaxTargetNodes = 5'000'000;

std::string grouped(long long n) {
  // Built forwards, not with string::insert (GCC 12 reports a false -Wrestrict there).
  const std::string digits = std::to_string(n < 0 ? -n : n);
  std::string s = n < 0 ? "-" : "";
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) s += ',';
    s += digits[i];
  }
  return s;
}

// The thread count is process-wide state: put it back however the benchmark ends.
struct RestoreOmpThreads {
  int previous = omp_get_max_threads();
  ~RestoreOmpThreads() { omp_set_num_threads(previous); }
};

void validate(const RealtimeBenchOptions& o) {
  std::vector<std::string> dynamic;
  for (const ModelEntry& e : model_registry())
    if (e.capabilities.dynamic) dynamic.push_back(e.name);
  if (std::find(dynamic.begin(), dynamic.end(), o.model) == dynamic.end())
    throw InputError(
        fmt::format("bench: model '{}' is not a dynamic model with a time step to time; use one of {}",
                    o.model, fmt::join(dynamic, ", ")));
  if (o.target_nodes.empty()) throw InputError("bench: --nodes needs at least one node count");
  for (int n : o.target_nodes)
    if (n < 1 || n > kMaxTargetNodes)
      throw InputError(
          fmt::format("bench: node count {} is out of range; use 1 .. {}", n, grouped(kMaxTargetNodes)));
  if (o.threads.empty()) throw InputError("bench: --threads needs at least one thread count");
  for (int t : o.threads)
    if (t < 1 || t > 1024)
      throw InputError(fmt::format("bench: thread count {} is out of range; use 1 .. 1024", t));
  if (o.steps < 1) throw InputError(fmt::format("bench: --steps {} must be >= 1", o.steps));
  if (o.warmup_steps < 0) throw InputError(fmt::format("bench: --warmup {} must be >= 0", o.warmup_steps));
}

std::vector<std::string> bench_overrides(const RealtimeBenchOptions& o, double ramp_s, double spacing_m) {
  return timed_scene_overrides(o.model, o.overrides, o.warmup_steps + o.steps, ramp_s, spacing_m);
}

RealtimeBenchRow time_configuration(const RealtimeBenchOptions& o, const Scene& scene, int target,
                                    int threads, double spacing_m) {
  omp_set_num_threads(threads);
  Simulation sim(scene);
  Model& model = sim.model();
  if (model.num_steps() < o.warmup_steps + o.steps)
    throw std::logic_error(fmt::format("bench: the model plans {} steps, {} are needed", model.num_steps(),
                                       o.warmup_steps + o.steps));
  for (int k = 1; k <= o.warmup_steps; ++k) model.advance(k);
  std::vector<double> wall_ms(static_cast<std::size_t>(o.steps));
  std::vector<int> substeps(wall_ms.size());
  for (int i = 0; i < o.steps; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const StepReport rep = model.advance(o.warmup_steps + 1 + i);
    wall_ms[static_cast<std::size_t>(i)] =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    substeps[static_cast<std::size_t>(i)] = rep.iterations;
  }

  RealtimeBenchRow r;
  r.target_nodes = target;
  r.nodes = static_cast<int>(sim.discretization().num_nodes());
  r.node_spacing_m = spacing_m;
  r.mean_neighbours = sim.discretization().mean_neighbours();
  r.threads = threads;
  r.warmup_steps = o.warmup_steps;
  r.steps = o.steps;
  r.setup_s = sim.setup_seconds();
  r.model_info = model.info();
  // The explicit model's substep count per step can vary (its dt does not divide 1 ms): take the median.
  std::nth_element(substeps.begin(), substeps.begin() + static_cast<long>(substeps.size() / 2),
                   substeps.end());
  r.substeps = substeps[substeps.size() / 2];
  if (r.model_info.contains("substeps_per_step") && r.model_info["substeps_per_step"].is_number_integer())
    r.substeps = r.model_info["substeps_per_step"].get<int>();
  if (r.model_info.contains("iterations") && r.model_info["iterations"].is_number_integer())
    r.iterations = r.model_info["iterations"].get<int>();
  std::vector<double> sorted = wall_ms;
  std::sort(sorted.begin(), sorted.end());
  r.median_ms = quantile(sorted, 0.5);
  r.p10_ms = quantile(sorted, 0.1);
  r.p90_ms = quantile(sorted, 0.9);
  r.max_ms = sorted.back();
  r.mean_ms = std::accumulate(sorted.begin(), sorted.end(), 0.0) / static_cast<double>(sorted.size());
  r.steps_per_s = 1000.0 / r.median_ms;
  r.realtime_factor = kBenchStepS * 1e3 / r.median_ms;
  r.meets_haptic = r.median_ms <= kHapticMaxMs;
  r.meets_visual = r.steps_per_s >= kVisualMinStepsPerS;
  return r;
}

// Verdict for one target: met if any configuration with enough nodes on <= 2 threads meets it.
nlohmann::json verdict(const std::vector<RealtimeBenchRow>& rows, int min_nodes,
                       bool RealtimeBenchRow::*meets) {
  nlohmann::json best = nullptr;
  bool any = false;
  for (const auto& r : rows) {
    if (r.nodes < min_nodes || r.threads > kTargetMaxThreads) continue;
    any = true;
    if (r.*meets && (best.is_null() || r.nodes > best["nodes"].get<int>()))
      best = {{"nodes", r.nodes}, {"threads", r.threads}, {"median_ms", r.median_ms}};
  }
  if (!any) return {{"met", nullptr}, {"largest_meeting", nullptr}};  // no configuration qualifies
  return {{"met", !best.is_null()}, {"largest_meeting", best}};
}

}  // namespace

std::vector<std::string> timed_scene_overrides(const std::string& model, const std::vector<std::string>& user,
                                               int total_steps, double ramp_s, double spacing_m) {
  const double duration_s = total_steps * kBenchStepS;
  std::vector<std::string> s = {kBenchDefaultOverride, kBenchLayersOverride};
  s.insert(s.end(), user.begin(), user.end());
  s.push_back("model=" + model);
  // The plain lattice whose spacing find_tube_resolution chose (a scene may fit its lattice to a patch, which
  // sets the counts of columns and cross-sections itself).
  s.push_back("geometry.fit_lattice_to_patch=none");
  s.push_back(fmt::format("geometry.node_spacing_m={:.17g}", spacing_m));
  s.push_back(fmt::format("{}.output_interval_s={:.17g}", model, kBenchStepS));
  s.push_back(fmt::format("{}.duration_s={:.17g}", model, duration_s));
  // Keep the scene's ramp, but finish it within the run so the timed steps see the full load.
  s.push_back(fmt::format("{}.ramp_time_s={:.17g}", model, std::min(ramp_s, duration_s)));
  return s;
}

TubeResolution find_tube_resolution(const GeometrySpec& geometry, int target_nodes) {
  if (geometry.type != "tube")
    throw InputError(
        fmt::format("bench: the scene's geometry is a '{}'; the benchmark varies "
                    "geometry.node_spacing_m of a tube",
                    geometry.type));
  if (target_nodes < 1) throw InputError(fmt::format("bench: node count {} must be >= 1", target_nodes));
  GeometrySpec g = geometry;
  // The plain lattice of each spacing (timed_scene_overrides asks for it too): a lattice fitted to a patch
  // fixes its counts of columns and cross-sections.
  g.fit_lattice_to_patch = "none";
  g.tube.angular_nodes = g.tube.axial_nodes = 0;
  auto count = [&](double spacing) {
    g.tube.node_spacing_m = spacing;
    return static_cast<int>(build_geometry(g).positions.size());
  };
  // Bracket lo (count >= target) and hi (count < target), starting from a guess with count ~ spacing^-3;
  // small factors keep every trial cloud within ~2x of the target (they are built in full).
  double guess = geometry.tube.node_spacing_m;
  guess *= std::cbrt(static_cast<double>(count(guess)) / target_nodes);
  double lo = guess, hi = guess;
  int n_lo = count(guess), n_hi = n_lo;
  constexpr double kFactor = 1.25;
  constexpr int kMaxExpansions = 80;
  for (int i = 0; n_hi >= target_nodes && i < kMaxExpansions; ++i) n_hi = count(hi *= kFactor);
  for (int i = 0; n_lo < target_nodes && i < kMaxExpansions; ++i) n_lo = count(lo /= kFactor);
  if (n_hi >= target_nodes) return {hi, n_hi};  // below the coarsest cloud (min layers x 8 x 2)
  if (n_lo < target_nodes) return {lo, n_lo};
  // The count is a non-increasing step function of the spacing: bisect (geometrically) to its jump.
  while (hi / lo > 1.0 + 1e-9) {
    const double mid = std::sqrt(lo * hi);
    const int n = count(mid);
    (n >= target_nodes ? lo : hi) = mid;
    (n >= target_nodes ? n_lo : n_hi) = n;
    if (n == target_nodes) break;
  }
  return n_lo - target_nodes <= target_nodes - n_hi ? TubeResolution{lo, n_lo} : TubeResolution{hi, n_hi};
}

RealtimeBenchReport run_realtime_bench(const RealtimeBenchOptions& o) {
  validate(o);
  auto say = [&](const std::string& line) {
    if (o.progress) o.progress(line);
  };
  const Scene base = load_scene(o.scene_path, [&] {
    std::vector<std::string> s = {kBenchDefaultOverride, kBenchLayersOverride};
    s.insert(s.end(), o.overrides.begin(), o.overrides.end());
    s.push_back("model=" + o.model);
    return s;
  }());
  const double ramp_s = find_model(o.model).schedule(base.own_model_settings()).ramp_time_s;
  const unsigned hw = std::thread::hardware_concurrency();
  RestoreOmpThreads restore;

  RealtimeBenchReport report;
  const nlohmann::json machine = machine_info();
  report.header = {
      {"benchmark", "realtime"},
      {"date_utc", machine["date_utc"]},
      {"machine",
       {{"cpu_model", machine["cpu_model"]},
        {"hardware_concurrency", hw},
        {"omp_num_procs", omp_get_num_procs()},
        {"omp_max_threads", restore.previous},
        {"load_average_1min_start", load_average_1min()}}},
      {"build",
       {{"type", machine["build_type"]}, {"ndebug", machine["ndebug"]}, {"compiler", machine["compiler"]}}},
      {"scene", o.scene_path},
      {"scene_name", base.name},
      {"model", o.model},
      {"overrides", o.overrides},
      {"default_overrides", {kBenchDefaultOverride, kBenchLayersOverride}},
      {"step_ms", kBenchStepS * 1e3},
      {"warmup_steps", o.warmup_steps},
      {"steps", o.steps},
      {"ramp_time_s", std::min(ramp_s, (o.warmup_steps + o.steps) * kBenchStepS)},
      {"statistic", "wall time of Model::advance per 1 ms step, steady_clock; median, p10/p90 interpolated"},
      {"targets",
       {{"haptic",
         {{"max_median_ms", kHapticMaxMs},
          {"min_nodes", kHapticMinNodes},
          {"max_threads", kTargetMaxThreads}}},
        {"visual",
         {{"min_steps_per_s", kVisualMinStepsPerS},
          {"min_nodes", kVisualMinNodes},
          {"max_threads", kTargetMaxThreads}}}}}};

  for (int target : o.target_nodes) {
    const TubeResolution res = find_tube_resolution(base.geometry, target);
    const double off = static_cast<double>(res.nodes - target) / target;
    say(fmt::format("target {} nodes: node_spacing_m = {:.4g} gives {} nodes ({:+.1f} %){}", grouped(target),
                    res.node_spacing_m, grouped(res.nodes), 100.0 * off,
                    std::abs(off) > kBenchNodeTolerance ? " - no closer tube count exists" : ""));
    const Scene scene = load_scene(o.scene_path, bench_overrides(o, ramp_s, res.node_spacing_m));
    for (int threads : o.threads) {
      RealtimeBenchRow r = time_configuration(o, scene, target, threads, res.node_spacing_m);
      say(fmt::format(
          "nodes {}, {} thread{}: {} steps, median {:.4g} ms/step (p10 {:.4g}, p90 {:.4g}, max {:.4g}), "
          "{:.0f} steps/s, {:.3g}x real time{}",
          grouped(r.nodes), threads, threads == 1 ? "" : "s", r.steps, r.median_ms, r.p10_ms, r.p90_ms,
          r.max_ms, r.steps_per_s, r.realtime_factor,
          hw > 0 && static_cast<unsigned>(threads) > hw ? " (more threads than cores)" : ""));
      if (report.header.find("model_info") == report.header.end()) report.header["model_info"] = r.model_info;
      report.rows.push_back(std::move(r));
    }
  }
  report.header["machine"]["load_average_1min_end"] = load_average_1min();
  report.header["verdicts"] = {
      {"haptic", verdict(report.rows, kHapticMinNodes, &RealtimeBenchRow::meets_haptic)},
      {"visual", verdict(report.rows, kVisualMinNodes, &RealtimeBenchRow::meets_visual)}};
  return report;
}

nlohmann::json realtime_bench_json(const RealtimeBenchReport& report) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : report.rows)
    rows.push_back({{"target_nodes", r.target_nodes},
                    {"nodes", r.nodes},
                    {"node_spacing_m", r.node_spacing_m},
                    {"mean_neighbours", r.mean_neighbours},
                    {"threads", r.threads},
                    {"substeps", r.substeps},
                    {"iterations", r.iterations ? nlohmann::json(*r.iterations) : nlohmann::json(nullptr)},
                    {"warmup_steps", r.warmup_steps},
                    {"steps", r.steps},
                    {"median_ms", r.median_ms},
                    {"p10_ms", r.p10_ms},
                    {"p90_ms", r.p90_ms},
                    {"mean_ms", r.mean_ms},
                    {"max_ms", r.max_ms},
                    {"steps_per_s", r.steps_per_s},
                    {"realtime_factor", r.realtime_factor},
                    {"meets_haptic", r.meets_haptic},
                    {"meets_visual", r.meets_visual},
                    {"setup_s", r.setup_s},
                    {"model_info", r.model_info}});
  return {{"header", report.header}, {"results", rows}};
}

std::string realtime_bench_csv(const RealtimeBenchReport& report) {
  std::string s =
      "target_nodes,nodes,node_spacing_m,mean_neighbours,threads,substeps,iterations,warmup_steps,steps,"
      "median_ms,"
      "p10_ms,p90_ms,mean_ms,max_ms,steps_per_s,realtime_factor,meets_haptic,meets_visual,setup_s\n";
  for (const auto& r : report.rows)
    s += fmt::format(
        "{},{},{:.9g},{:.4g},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{},{:.4g}\n",
        r.target_nodes, r.nodes, r.node_spacing_m, r.mean_neighbours, r.threads, r.substeps,
        r.iterations ? std::to_string(*r.iterations) : "", r.warmup_steps, r.steps, r.median_ms, r.p10_ms,
        r.p90_ms, r.mean_ms, r.max_ms, r.steps_per_s, r.realtime_factor, r.meets_haptic ? "true" : "false",
        r.meets_visual ? "true" : "false", r.setup_s);
  return s;
}

std::string realtime_bench_table(const RealtimeBenchReport& report) {
  const auto& h = report.header;
  std::string s =
      fmt::format("{} on {}: wall time per {:g} ms step, {} steps after {} warm-up ({})\n\n",
                  h["model"].get<std::string>(), h["scene"].get<std::string>(), h["step_ms"].get<double>(),
                  h["steps"].get<int>(), h["warmup_steps"].get<int>(), h["date_utc"].get<std::string>());
  s += fmt::format("{:>8} {:>7} {:>8} {:>5} {:>9} {:>9} {:>9} {:>9} {:>8} {:>9} {:>6} {:>6}\n", "nodes",
                   "threads", "substeps", "iter", "median_ms", "p10_ms", "p90_ms", "max_ms", "steps/s",
                   "RT factor", "haptic", "visual");
  for (const auto& r : report.rows)
    s += fmt::format(
        "{:>8} {:>7} {:>8} {:>5} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f} {:>8.1f} {:>9.3f} {:>6} {:>6}\n",
        grouped(r.nodes), r.threads, r.substeps, r.iterations ? std::to_string(*r.iterations) : "-",
        r.median_ms, r.p10_ms, r.p90_ms, r.max_ms, r.steps_per_s, r.realtime_factor,
        r.meets_haptic ? "yes" : "no", r.meets_visual ? "yes" : "no");
  auto line = [&](const char* key, const std::string& what) {
    const auto& v = h["verdicts"][key];
    std::string state = "not measured (no configuration with enough nodes on <= 2 threads)";
    if (!v["met"].is_null()) {
      state = "NOT MET";
      if (v["met"].get<bool>()) {
        const auto& b = v["largest_meeting"];
        state = fmt::format("met (largest: {} nodes, {} thread(s), median {:.3f} ms)",
                            grouped(b["nodes"].get<int>()), b["threads"].get<int>(),
                            b["median_ms"].get<double>());
      }
    }
    s += fmt::format("{}: {}\n", what, state);
  };
  s += "\n";
  line("haptic", fmt::format("haptic target (median <= {:g} ms at >= {} nodes, <= {} threads)", kHapticMaxMs,
                             grouped(kHapticMinNodes), kTargetMaxThreads));
  line("visual", fmt::format("visual target (>= {:g} steps/s at >= {} nodes, <= {} threads)",
                             kVisualMinStepsPerS, grouped(kVisualMinNodes), kTargetMaxThreads));
  return s;
}

}  // namespace vascsim
