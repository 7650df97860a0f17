// The haptic session (docs/haptics.md): the scripted device poses the catheter through the 1 kHz loop
// while xpbd deforms a block. Lockstep sessions replay bit for bit from their recording; a realtime
// session keeps its force finite and within the clamp; bad device files stop the CLI with exit code 2.

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "support/run_helpers.hpp"
#include "vascsim/app/cli.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/interaction/scripted_device.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/run/haptic_session.hpp"

namespace vascsim {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("vascsim-haptic-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// force_history.csv without its last column (the wall time of each step, which no replay reproduces).
std::string history_without_wall_time(const fs::path& f) {
  std::ifstream in(f);
  std::string line, text;
  while (std::getline(in, line)) text += line.substr(0, line.rfind(',')) + "\n";
  return text;
}

TEST(HapticSession, LockstepPressReplaysBitIdentically) {
  const fs::path a = fresh_dir("record"), b = fresh_dir("replay");
  HapticRunOptions first;
  first.out_dir = a;
  const auto s1 = run_haptic_session(test::haptic_block_scene(test::kCoarseHapticBlock), first);
  const auto& h = s1["haptics"];
  EXPECT_EQ(h["ticks"].get<std::size_t>(), 251u);  // 0.25 s at 1 kHz, both ends
  EXPECT_EQ(h["simulation_steps"].get<std::size_t>(), 251u);
  // The catheter pressed 0.8 mm: the tissue pushes it back up (+z), and the device got a force.
  const double fmax = h["max_force_on_tool_n"].get<double>();
  EXPECT_GT(fmax, 1e-3);
  EXPECT_EQ(h["loop"]["nan_events"].get<std::uint64_t>(), 0u);
  const RecordedSession rec = read_session_recording(a / "session.csv");
  ASSERT_EQ(rec.forces.size(), 251u);
  double up = 0.0;
  for (const auto& f : rec.forces) {
    ASSERT_TRUE(f.force_n.allFinite());
    EXPECT_LE(f.force_n.norm(), 0.88 + 1e-12);
    up = std::max(up, f.force_n.z());
  }
  EXPECT_GT(up, 0.5 * fmax);  // the device is pushed up, as the tool is

  HapticRunOptions again;
  again.out_dir = b;
  again.replay = a / "session.csv";
  const auto s2 = run_haptic_session(test::haptic_block_scene(test::kCoarseHapticBlock), again);
  EXPECT_TRUE(s2["haptics"]["replay"]["bit_identical"].get<bool>());
  EXPECT_EQ(s2["haptics"]["replay"]["max_force_difference_n"].get<double>(), 0.0);
  // The same deformation: the force history (17 digits) is the same text.
  const std::string history = history_without_wall_time(a / "force_history.csv");
  EXPECT_EQ(std::count(history.begin(), history.end(), '\n'), 252);
  EXPECT_EQ(history, history_without_wall_time(b / "force_history.csv"));
  fs::remove_all(a);
  fs::remove_all(b);
}

// The haptic thread at wall-clock 1 kHz while the simulation steps on this thread. Shared machine: only
// generous bounds (rate within 20 % of nominal); what matters is no NaN and the clamp.
TEST(HapticSession, RealtimePressStaysWithinTheClamp) {
  const fs::path d = fresh_dir("realtime");
  HapticRunOptions opt;
  opt.out_dir = d;
  opt.mode = "realtime";
  const auto s = run_haptic_session(test::haptic_block_scene({"haptics.force_limit_n=0.05"}), opt);
  const auto& loop = s["haptics"]["loop"];
  std::printf(
      "[ session  ] realtime: %.1f Hz, jitter p50/p99/max %.3f/%.3f/%.3f ms, %zu simulation steps at %.1f "
      "Hz, "
      "force latency mean %.2f ms\n",
      loop["achieved_rate_hz"].get<double>(), loop["jitter_p50_ms"].get<double>(),
      loop["jitter_p99_ms"].get<double>(), loop["jitter_max_ms"].get<double>(),
      s["haptics"]["simulation_steps"].get<std::size_t>(), s["haptics"]["deformation_rate_hz"].get<double>(),
      loop["force_latency_mean_ms"].get<double>());
  EXPECT_GT(loop["achieved_rate_hz"].get<double>(), 800.0);
  EXPECT_LT(loop["achieved_rate_hz"].get<double>(), 1200.0);
  EXPECT_EQ(loop["nan_events"].get<std::uint64_t>(), 0u);
  EXPECT_GE(s["haptics"]["simulation_steps"].get<std::size_t>(), 1u);  // TSan builds step ~1 per 0.25 s
  EXPECT_LE(loop["max_force_sent_n"].get<double>(), 0.05 + 1e-12);
  fs::remove_all(d);
}

// Any Device can drive a session (the path a hardware device takes); it then needs haptics.duration_s.
TEST(HapticSession, TakesAnExternalDevice) {
  const fs::path d = fresh_dir("external");
  ScriptedDevice device(read_trajectory(test::source_path("tests/data/haptic-press.csv")));
  HapticRunOptions opt;
  opt.out_dir = d;
  opt.device = &device;
  EXPECT_THROW(run_haptic_session(test::haptic_block_scene(), opt), InputError);
  const auto s = run_haptic_session(test::haptic_block_scene({"haptics.duration_s=0.02"}), opt);
  EXPECT_EQ(s["haptics"]["ticks"].get<std::size_t>(), 21u);
  EXPECT_EQ(device.sent_forces().size(), 21u);  // the loop sent every tick's force to this device
  fs::remove_all(d);
}

int run(const std::vector<std::string>& args, std::string& err_text) {
  std::ostringstream out, err;
  const int rc = run_cli(args, out, err);
  err_text = err.str();
  return rc;
}

// Any model whose registry entry says a device can drive it runs a session: quasi_static, one equilibrium
// per 50 ms frame (six frames, to keep the test short). The tool starts 0.2 mm above the block (no force at
// the first frame) and presses 0.8 mm into it; the session replays bit for bit like xpbd's.
TEST(HapticSession, QuasiStaticModelDrivesALockstepSession) {
  const fs::path a = fresh_dir("qs-record"), b = fresh_dir("qs-replay");
  const std::vector<std::string> sets = {"model=quasi_static", "quasi_static.frame_s=0.05",
                                         "haptics.ticks_per_step=50"};
  HapticRunOptions first;
  first.out_dir = a;
  const auto s1 = run_haptic_session(test::haptic_block_scene(sets), first);
  EXPECT_EQ(s1["model"], "quasi_static");
  EXPECT_EQ(s1["haptics"]["simulation_steps"].get<std::size_t>(), 6u);  // 251 ticks, one frame per 50
  std::ifstream in(a / "force_history.csv");
  std::string line;
  std::getline(in, line);  // header
  std::vector<double> forces;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (int c = 0; c <= 8; ++c) std::getline(row, cell, ',');  // column 8: force_magnitude_n
    forces.push_back(std::stod(cell));
  }
  ASSERT_EQ(forces.size(), 6u);
  EXPECT_EQ(forces.front(), 0.0);
  for (double f : forces) EXPECT_TRUE(std::isfinite(f));
  EXPECT_GT(*std::max_element(forces.begin(), forces.end()), 1e-3);
  HapticRunOptions again;
  again.out_dir = b;
  again.replay = a / "session.csv";
  const auto s2 = run_haptic_session(test::haptic_block_scene(sets), again);
  EXPECT_TRUE(s2["haptics"]["replay"]["bit_identical"].get<bool>());
}

// The slow press of the implicit-model session tests: 0.5 mm in 0.6 s into the block, then held.
fs::path write_slow_press(const fs::path& d) {
  std::ofstream(d / "slow-press.csv") << "time_s,x_m,y_m,z_m\n0,0.003,0.003,0.0031\n0.6,0.003,0.003,0.0026\n"
                                         "0.8,0.003,0.003,0.0026\n";
  return d / "slow-press.csv";
}

// An implicit-model session on the block with frames of `ticks_per_frame` ms (lockstep or realtime).
nlohmann::json implicit_session(const fs::path& trajectory, int ticks_per_frame, const std::string& mode,
                                const fs::path& out) {
  const std::string frame = std::to_string(ticks_per_frame * 1e-3);
  HapticRunOptions o;
  o.out_dir = out;
  o.mode = mode;
  return run_haptic_session(
      test::haptic_block_scene({"model=implicit", "implicit.frame_s=" + frame,
                                "implicit.output_interval_s=" + frame, "implicit.duration_s=0.8",
                                "haptics.ticks_per_step=" + std::to_string(ticks_per_frame),
                                "haptics.device.trajectory=" + trajectory.string()}),
      o);
}

// Columns of a CSV file with a header, by name, as numbers.
std::vector<std::vector<double>> csv_columns(const fs::path& file, const std::vector<std::string>& names) {
  std::ifstream in(file);
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> head;
  for (std::stringstream h(line); std::getline(h, cell, ',');) head.push_back(cell);
  std::vector<std::size_t> at;
  for (const auto& n : names)
    at.push_back(static_cast<std::size_t>(std::find(head.begin(), head.end(), n) - head.begin()));
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> all;
    for (std::stringstream r(line); std::getline(r, cell, ',');) all.push_back(std::stod(cell));
    std::vector<double> row;
    for (std::size_t a : at) row.push_back(all.at(a));
    rows.push_back(row);
  }
  return rows;
}

// The equilibrium force (z) against the tool's height, from a session's frames (force_history.csv),
// interpolated linearly in the height.
std::function<double(double)> equilibrium_by_height(const fs::path& session) {
  auto frames = csv_columns(session / "force_history.csv", {"tool_z_m", "force_z_n"});
  std::sort(frames.begin(), frames.end());
  return [frames](double z) {
    auto it = std::lower_bound(frames.begin(), frames.end(), std::vector<double>{z, -1e300});
    if (it == frames.begin()) return frames.front()[1];
    if (it == frames.end()) return frames.back()[1];
    const auto& a = *(it - 1);
    const auto& b = *it;
    return a[1] + (b[1] - a[1]) * (z - a[0]) / (b[0] - a[0]);
  };
}

struct TickComparison {
  int compared = 0;
  double worst = 0.0;  // relative
};

// Every tick's tissue force (haptic_ticks.csv) against the equilibrium at the tick's tool height, where that
// equilibrium exceeds 2 mN (the first 0.05 mm of the press, where a tenth of the force is below the ripple of
// a frame's discrete contact set), each within `bound` relative; every tick finite.
TickComparison compare_ticks(const fs::path& session, const std::function<double(double)>& equilibrium,
                             double bound) {
  TickComparison c;
  for (const auto& t : csv_columns(session / "haptic_ticks.csv", {"time_s", "tool_z_m", "tissue_fz_n"})) {
    EXPECT_TRUE(std::isfinite(t[2])) << "t = " << t[0];
    const double eq = equilibrium(t[1]);
    if (!(eq > 2e-3)) continue;
    ++c.compared;
    c.worst = std::max(c.worst, std::abs(t[2] - eq) / eq);
    EXPECT_LE(std::abs(t[2] - eq), bound * eq) << "t = " << t[0] << " s, tool z = " << t[1] << " m";
  }
  return c;
}

// Slow frames, deterministically: the implicit model in lockstep with frames of 50 ms (20 frames/s, as on a
// loaded machine), the haptic thread bridging 50 ticks per frame with the wall's linearised response and the
// candidate contacts. Every tick's tissue force must stay within 10 % (the bound for the force felt
// at 1 kHz) of the equilibrium at the tick's tool position, from a lockstep session with frames of 10 ms
// (converged, interpolated in the tool height). Measured: worst 8.3 %, median 0.9 % (10 ms frames against
// themselves between frames: worst 7.3 %).
TEST(HapticSession, ImplicitSlowFramesKeepEveryTickNearTheEquilibrium) {
  const fs::path d = fresh_dir("implicit-slow");
  const fs::path press = write_slow_press(d);
  implicit_session(press, 10, "lockstep", d / "frames-10ms");
  implicit_session(press, 50, "lockstep", d / "frames-50ms");
  const TickComparison c = compare_ticks(d / "frames-50ms", equilibrium_by_height(d / "frames-10ms"), 0.10);
  std::printf(
      "[ session  ] implicit, 50 ms frames in lockstep: %d ticks in contact, worst tick %.1f %% from the "
      "equilibrium\n",
      c.compared, 100 * c.worst);
  EXPECT_GT(c.compared, 500);
  fs::remove_all(d);
}

// The same in a realtime session: the haptic thread at wall-clock 1 kHz, the model on the other core as fast
// as it goes. The target, 10 % at every tick, is asserted deterministically by the lockstep test
// above; here the frames arrive when the shared machine lets them, a frame's force is a frame old when it
// lands, and each extrapolation spans two frames: measured 8-13 % at 40-58 frames/s with other jobs on the
// machine, and 15.3-16.4 % over a burst of ticks after a late frame at 85 frames/s with a build and a
// benchmark beside it (load 3), so the bound is 20 %. It presumes frames at most 50 ms apart (the lockstep
// test's regime): on a machine so loaded that the model's thread was held longer between two frames, the
// accuracy check is skipped (saying so, with the gap), while every tick must still be finite and within the
// clamp, and the loop must run.
TEST(HapticSession, ImplicitRealtimeTicksFollowTheEquilibrium) {
  const fs::path d = fresh_dir("implicit-realtime");
  const fs::path press = write_slow_press(d);
  implicit_session(press, 10, "lockstep", d / "lockstep");
  const auto s = implicit_session(press, 10, "realtime", d / "realtime");
  const double rate = s["haptics"]["deformation_rate_hz"].get<double>();
  const RecordedSession rec = read_session_recording(d / "realtime" / "session.csv");
  ASSERT_GT(rec.forces.size(), 500u);
  for (const ForceSample& f : rec.forces) {
    ASSERT_TRUE(f.force_n.allFinite());
    EXPECT_LE(f.force_n.norm(), 0.88 + 1e-12);
  }
  std::printf("[ session  ] implicit realtime: %.1f frames/s; %s; loop %.1f Hz, p99 jitter %.3f ms\n", rate,
              s["haptics"]["loop"]["scheduling"].get<std::string>().c_str(),
              s["haptics"]["loop"]["achieved_rate_hz"].get<double>(),
              s["haptics"]["loop"]["jitter_p99_ms"].get<double>());
  EXPECT_GT(s["haptics"]["loop"]["achieved_rate_hz"].get<double>(), 900.0);
  double gap = 0.0;  // the longest wall time between the poses of two consecutive frames
  const auto poses = csv_columns(d / "realtime" / "force_history.csv", {"pose_time_s"});
  for (std::size_t i = 1; i < poses.size(); ++i) gap = std::max(gap, poses[i][0] - poses[i - 1][0]);
  if (gap > 0.05)
    GTEST_SKIP() << "the machine held the model's thread for " << 1e3 * gap
                 << " ms between two frames (> 50 ms): tick accuracy not checked";
  const TickComparison c = compare_ticks(d / "realtime", equilibrium_by_height(d / "lockstep"), 0.2);
  std::printf(
      "[ session  ] implicit realtime: %d ticks in contact, worst tick %.1f %% from the equilibrium\n",
      c.compared, 100 * c.worst);
  EXPECT_GT(c.compared, 300);
  fs::remove_all(d);
}

// A model a device cannot drive is refused by the scene, naming the models that can.
TEST(HapticSession, ModelsNoDeviceCanDriveAreRefused) {
  try {
    test::haptic_block_scene({"model=explicit"});
    ADD_FAILURE() << "explicit accepted for a haptic session";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("xpbd"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("haptics"), std::string::npos) << e.what();
  }
}

// Bad device files: one clear line naming the file (and the line), exit code 2, before any set-up.
TEST(HapticSession, BadDeviceFilesExitWithCode2) {
  const fs::path d = fresh_dir("bad");
  const std::string header = "time_s,x_m,y_m,z_m\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"malformed.csv", header + "0,0.003,0.003\n"},
      {"backwards.csv", header + "0,0.003,0.003,0.0032\n0.1,0.003,0.003,0.003\n0.05,0.003,0.003,0.003\n"},
      {"nan.csv", header + "0,0.003,0.003,0.0032\n0.1,nan,0.003,0.003\n"},
      {"empty.csv", header}};
  for (const auto& [name, text] : cases) {
    std::ofstream(d / name) << text;
    std::string err;
    const int rc = run({"-q", "run", test::source_path("tests/data/haptic-block.json"), "--out",
                        (d / "out").string(), "--set", "haptics.device.trajectory=" + (d / name).string()},
                       err);
    EXPECT_EQ(rc, 2) << name << ": " << err;
    EXPECT_NE(err.find(name), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
  std::string err;
  EXPECT_EQ(run({"-q", "run", test::source_path("tests/data/haptic-block.json"), "--out",
                 (d / "out").string(), "--set", "haptics.device.trajectory=" + (d / "missing.csv").string()},
                err),
            2);
  EXPECT_NE(err.find("missing.csv"), std::string::npos) << err;
  EXPECT_EQ(run({"-q", "run", test::source_path("tests/data/haptic-block.json"), "--out",
                 (d / "out").string(), "--replay", (d / "nan.csv").string()},
                err),
            2);
  fs::remove_all(d);
}

}  // namespace
}  // namespace vascsim
