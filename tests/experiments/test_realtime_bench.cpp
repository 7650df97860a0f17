// The real-time benchmark (`vascsim bench`, experiments/realtime_bench.hpp) works as documented: it finds
// vein resolutions near the target node counts, reports every column with positive finite times, writes
// CSV and JSON, and rejects bad input with InputError / exit code 2. Functional only: speed is measured by
// `make bench-realtime`, never asserted. A tiny configuration (~400 nodes, 3 steps) keeps it ~1 s.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "vascsim/app/cli.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/realtime_bench.hpp"
#include "vascsim/scene/scene.hpp"

namespace {

namespace fs = std::filesystem;
using namespace vascsim;

const std::string kVein = std::string(VASCSIM_SOURCE_DIR) + "/scenes/vein-indent.json";

RealtimeBenchOptions tiny(const std::string& model = "xpbd") {
  RealtimeBenchOptions o;
  o.scene_path = kVein;
  o.model = model;
  o.target_nodes = {400};
  o.threads = {1};
  o.steps = 3;
  o.warmup_steps = 1;
  return o;
}

bool positive_finite(double v) {
  return std::isfinite(v) && v > 0.0;
}

TEST(RealtimeBench, FindsVeinResolutionsNearTheTargets) {
  // The plain lattice (the bundled scene fits its lattice to the indenter's patch, which fixes its counts).
  const GeometrySpec geometry = load_scene(kVein, {"geometry.fit_lattice_to_patch=none"}).geometry;
  for (int target : {400, 1000, 3000, 10000, 30000}) {
    const TubeResolution r = find_tube_resolution(geometry, target);
    EXPECT_NEAR(r.nodes, target, kBenchNodeTolerance * target) << "target " << target;
    EXPECT_GT(r.node_spacing_m, 0.0);
    GeometrySpec g = geometry;
    g.tube.node_spacing_m = r.node_spacing_m;
    EXPECT_EQ(make_tube(g.tube).positions.size(), static_cast<std::size_t>(r.nodes)) << "target " << target;
  }
}

TEST(RealtimeBench, TinyRunReportsEveryColumn) {
  RealtimeBenchOptions o = tiny();
  int progress_lines = 0;
  o.progress = [&](const std::string&) { ++progress_lines; };
  const RealtimeBenchReport rep = run_realtime_bench(o);
  EXPECT_GE(progress_lines, 2);  // the resolution found and the configuration timed
  ASSERT_EQ(rep.rows.size(), 1u);
  const RealtimeBenchRow& r = rep.rows[0];
  EXPECT_EQ(r.target_nodes, 400);
  EXPECT_NEAR(r.nodes, 400, kBenchNodeTolerance * 400);
  EXPECT_EQ(r.threads, 1);
  EXPECT_EQ(r.steps, 3);
  EXPECT_EQ(r.warmup_steps, 1);
  EXPECT_GE(r.substeps, 1);
  ASSERT_TRUE(r.iterations.has_value());
  EXPECT_GE(*r.iterations, 1);
  for (double v : {r.median_ms, r.p10_ms, r.p90_ms, r.mean_ms, r.max_ms, r.steps_per_s, r.realtime_factor})
    EXPECT_TRUE(positive_finite(v)) << v;
  EXPECT_LE(r.p10_ms, r.median_ms);
  EXPECT_LE(r.median_ms, r.p90_ms);
  EXPECT_LE(r.p90_ms, r.max_ms);
  EXPECT_NEAR(r.steps_per_s * r.median_ms, 1000.0, 1e-9);
  EXPECT_EQ(r.meets_haptic, r.median_ms <= 1.0);
  EXPECT_EQ(r.meets_visual, r.steps_per_s >= 85.0);

  const nlohmann::json j = realtime_bench_json(rep);
  for (const char* key :
       {"date_utc", "machine", "build", "scene", "model", "model_info", "targets", "verdicts"})
    EXPECT_TRUE(j["header"].contains(key)) << key;
  EXPECT_EQ(j["header"]["model_info"]["model"], "xpbd");
  EXPECT_GE(j["header"]["machine"]["hardware_concurrency"].get<int>(), 0);
  // Only 400 nodes: no configuration qualifies for either target.
  EXPECT_TRUE(j["header"]["verdicts"]["haptic"]["met"].is_null());
  ASSERT_EQ(j["results"].size(), 1u);
  for (const char* key : {"nodes", "threads", "substeps", "iterations", "median_ms", "p10_ms", "p90_ms",
                          "mean_ms", "steps_per_s", "realtime_factor", "meets_haptic", "meets_visual"})
    EXPECT_TRUE(j["results"][0].contains(key)) << key;

  std::istringstream csv(realtime_bench_csv(rep));
  std::string header, row, extra;
  ASSERT_TRUE(std::getline(csv, header));
  ASSERT_TRUE(std::getline(csv, row));
  EXPECT_FALSE(std::getline(csv, extra));
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), std::count(row.begin(), row.end(), ','));
  EXPECT_NE(header.find("median_ms"), std::string::npos);
  EXPECT_NE(realtime_bench_table(rep).find("haptic target"), std::string::npos);
}

TEST(RealtimeBench, BadInputIsAnInputError) {
  auto with = [](auto change) {
    RealtimeBenchOptions o = tiny();
    change(o);
    return o;
  };
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.target_nodes = {0}; })), InputError);
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.target_nodes = {}; })), InputError);
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.threads = {0}; })), InputError);
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.steps = 0; })), InputError);
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.warmup_steps = -1; })), InputError);
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.model = "no_such_model"; })), InputError);
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.model = "quasi_static"; })), InputError);
  EXPECT_THROW(run_realtime_bench(with([](auto& o) { o.scene_path = kVein + ".missing"; })), InputError);
  EXPECT_THROW(find_tube_resolution(load_scene(kVein).geometry, 0), InputError);
}

TEST(RealtimeBench, CommandLineWritesCsvAndJsonAndExitsTwoOnBadInput) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("vascsim_bench_" + std::to_string(::getpid()));
  std::ostringstream out, err;
  const int code = run_cli({"bench", kVein, "--nodes", "400", "--threads", "1", "--steps", "2", "--warmup",
                            "1", "--out", (dir / "b.csv").string(), "--out", (dir / "b.json").string()},
                           out, err);
  EXPECT_EQ(code, 0) << err.str();
  EXPECT_TRUE(fs::exists(dir / "b.csv"));
  std::ifstream json_file(dir / "b.json");
  const auto j = nlohmann::json::parse(json_file);
  EXPECT_EQ(j["results"].size(), 1u);
  EXPECT_NE(out.str().find("median_ms"), std::string::npos);
  fs::remove_all(dir);

  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"bench", kVein, "--model", "no_such_model"},
        std::vector<std::string>{"bench", kVein, "--nodes", "0"},
        std::vector<std::string>{"bench", kVein, "--steps", "0"},
        std::vector<std::string>{"bench", kVein, "--out", (dir / "b.txt").string()}}) {
    std::ostringstream o2, e2;
    EXPECT_EQ(run_cli(args, o2, e2), 2) << args[2] << ": " << e2.str();
    EXPECT_NE(e2.str().find("bench:"), std::string::npos) << e2.str();
  }
}

}  // namespace
