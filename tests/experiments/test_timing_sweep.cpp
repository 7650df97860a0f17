// `vascsim experiment timing` (experiments/timing_sweep.hpp): one point on a coarse vein, its JSON round
// trip, and the command's --point / --merge path (a fanned-out sweep).

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "vascsim/app/cli.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/measured_indicators.hpp"
#include "vascsim/experiments/timing_sweep.hpp"

namespace vascsim {
namespace {

namespace fs = std::filesystem;
const std::string kVein = std::string(VASCSIM_SOURCE_DIR) + "/scenes/vein-indent.json";

// Timings are reported, never asserted: only that they are positive and consistent.
TEST(TimingSweep, OnePointTimesSimulationAndSurfaceMapSeparately) {
  TimingSweepOptions o;
  o.scene_path = kVein;
  o.steps = 3;
  o.warmup_steps = 1;
  const TimingPoint p = run_timing_point(o, "filling", 400);
  EXPECT_GT(p.nodes, 0);
  EXPECT_GT(p.surface_vertices, 0);
  EXPECT_NEAR(p.step_s, 1e-3, 1e-12);
  EXPECT_GT(p.simulation_median_ms, 0.0);
  EXPECT_GT(p.surface_map_median_ms, 0.0);
  EXPECT_NEAR(p.frames_per_s, 1000.0 / (p.simulation_median_ms + p.surface_map_median_ms), 1e-9);
  EXPECT_TRUE(p.machine.contains("cpu_model"));
  const TimingPoint q = timing_point_from_json(timing_point_json(p));
  EXPECT_EQ(q.model, p.model);
  EXPECT_EQ(q.nodes, p.nodes);
  EXPECT_EQ(q.simulation_median_ms, p.simulation_median_ms);
  EXPECT_THROW(run_timing_point(o, "quasi_static", 400), InputError);
}

// The AHP figures (docs/ahp.md): each model at its largest node count, the force error from rms_error.json,
// the comparison's reference left out of it. Copies of the inputs: exact.
TEST(TimingSweep, AhpMeasurementsTakeTheLargestNodeCountAndTheForceErrors) {
  TimingPoint a, b;
  a.model = b.model = "m";
  a.nodes = 100, a.simulation_median_ms = 1.0, a.frames_per_s = 900.0;
  b.nodes = 400, b.simulation_median_ms = 4.0, b.frames_per_s = 240.0;
  const nlohmann::json rms = {
      {"reference", "ref"},
      {"models", {{{"model", "ref"}, {"rms_percent", 0.0}}, {{"model", "m"}, {"rms_percent", 12.5}}}}};
  const nlohmann::json j = ahp_measurements({a, b}, rms, "test");
  ASSERT_EQ(j["models"].size(), 1u);
  EXPECT_EQ(j["models"][0]["id"], "m");
  EXPECT_EQ(j["models"][0]["nodes"], 400);
  EXPECT_EQ(j["models"][0]["update_time_ms"].get<double>(), 4.0);
  EXPECT_EQ(j["models"][0]["visual_refresh_rate_hz"].get<double>(), 240.0);
  EXPECT_EQ(j["models"][0]["force_rms_error_percent"].get<double>(), 12.5);
}

TEST(TimingSweep, CommandRunsOnePointThenMerges) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("vascsim_timing_" + std::to_string(::getpid()));
  std::ostringstream out, err;
  ASSERT_EQ(run_cli({"-q", "experiment", "timing", kVein, "--point", "filling:400", "--steps", "2",
                     "--warmup", "0", "--out", dir.string()},
                    out, err),
            0)
      << err.str();
  EXPECT_TRUE(fs::exists(dir / "points" / "filling-400.json"));
  std::ostringstream out2, err2;
  ASSERT_EQ(run_cli({"-q", "experiment", "timing", kVein, "--merge", "--no-plot", "--out", dir.string()},
                    out2, err2),
            0)
      << err2.str();
  std::ifstream csv(dir / "timing.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_NE(header.find("surface_map_median_ms"), std::string::npos);
  EXPECT_EQ(row.rfind("filling,400,", 0), 0u) << row;
  EXPECT_TRUE(fs::exists(dir / "ahp_measurements.json"));
  std::ostringstream out3, err3;
  EXPECT_EQ(run_cli({"experiment", "timing", kVein, "--point", "filling", "--out", dir.string()}, out3, err3),
            2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace vascsim
