// The device layer (src/vascsim/interaction/, docs/devices.md): trajectory interpolation, the
// trajectory and recording files with every class of bad input, bit-identical record/replay, the
// scripted device's force log and the mouse/keyboard mapping. Everything runs in well under a second.

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "vascsim/core/error.hpp"
#include "vascsim/interaction/device.hpp"
#include "vascsim/interaction/mouse_keyboard_device.hpp"
#include "vascsim/interaction/scripted_device.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/interaction/trajectory.hpp"

namespace {

namespace fs = std::filesystem;
using namespace vascsim;

// ---------------------------------------------------------------------------------------------
// Helpers

/// A per-process scratch folder in the system temp directory.
fs::path scratch() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("vascsim_devices_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p;
}

/// The InputError message of reading `file` (a test failure if there is none).
std::string read_error(const fs::path& file) {
  try {
    read_trajectory(file);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << file;
  return {};
}

/// Asserts that one-line `message` names `file` and contains each of `parts`.
void expect_message(const std::string& message, const fs::path& file, const std::vector<std::string>& parts) {
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  for (const auto& p : parts)
    EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

bool same_bits(const DevicePose& a, const DevicePose& b) {
  bool same = same_bits(a.time_s, b.time_s) && a.buttons == b.buttons;
  for (int k = 0; k < 3; ++k) same = same && same_bits(a.position_m[k], b.position_m[k]);
  for (int k = 0; k < 4; ++k) same = same && same_bits(a.orientation.coeffs()[k], b.orientation.coeffs()[k]);
  return same;
}

DevicePose sample(double t, const Vec3& p, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity(),
                  std::uint32_t buttons = 0) {
  return DevicePose{t, p, q, buttons};
}

Eigen::Quaterniond about_z(double angle_rad) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle_rad, Vec3::UnitZ()));
}

// ---------------------------------------------------------------------------------------------
// Interpolation

TEST(TrajectoryInterpolation, ExactAtSamplesLinearBetweenClampedOutside) {
  const Trajectory tr({sample(0.0, Vec3(0, 0, 0), about_z(0.0), 1),
                       sample(1.0, Vec3(1, 2, 3), about_z(0.3), 2),
                       sample(3.0, Vec3(1, 0, -1), about_z(0.6), 4)});
  for (const auto& s : tr.samples()) EXPECT_TRUE(same_bits(tr.at(s.time_s), s));

  const DevicePose mid = tr.at(0.5);
  EXPECT_EQ(mid.time_s, 0.5);
  EXPECT_NEAR((mid.position_m - Vec3(0.5, 1.0, 1.5)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((tr.at(2.5).position_m - Vec3(1.0, 0.5, 0.0)).norm(), 0.0, 1e-15);
  // Buttons hold the earlier sample's value up to the next sample.
  EXPECT_EQ(tr.at(0.999).buttons, 1u);
  EXPECT_EQ(tr.at(1.0).buttons, 2u);
  EXPECT_EQ(tr.at(2.999).buttons, 2u);

  // Clamped: before the first sample the first pose, after the last the last, with the queried time.
  const DevicePose before = tr.at(-5.0), after = tr.at(10.0);
  EXPECT_EQ(before.time_s, -5.0);
  EXPECT_EQ(before.position_m, tr.samples().front().position_m);
  EXPECT_EQ(before.buttons, 1u);
  EXPECT_EQ(after.position_m, tr.samples().back().position_m);
  EXPECT_EQ(after.orientation.coeffs(), tr.samples().back().orientation.coeffs());
  EXPECT_EQ(after.buttons, 4u);
}

TEST(TrajectoryInterpolation, SlerpHalfwayAngleAndShortestArc) {
  const double angle = std::numbers::pi / 2;
  const Trajectory tr({sample(0.0, Vec3::Zero()), sample(2.0, Vec3::Zero(), about_z(angle))});
  const Eigen::Quaterniond half = tr.at(1.0).orientation;
  EXPECT_NEAR(half.angularDistance(Eigen::Quaterniond::Identity()), angle / 2, 1e-12);
  EXPECT_NEAR(half.angularDistance(about_z(angle / 2)), 0.0, 1e-12);
  EXPECT_NEAR(half.norm(), 1.0, 1e-14);
  // A quarter of the way gives a quarter of the angle (constant angular velocity).
  EXPECT_NEAR(tr.at(0.5).orientation.angularDistance(about_z(angle / 4)), 0.0, 1e-12);

  // -q is the same rotation; interpolation still takes the 45 degree path, not the 315 degree one.
  Eigen::Quaterniond flipped = about_z(angle);
  flipped.coeffs() *= -1.0;
  const Trajectory tr2({sample(0.0, Vec3::Zero()), sample(2.0, Vec3::Zero(), flipped)});
  EXPECT_NEAR(tr2.at(1.0).orientation.angularDistance(about_z(angle / 2)), 0.0, 1e-12);
}

TEST(TrajectoryInterpolation, SingleSampleAndQuaternionNormalisation) {
  const Trajectory one({sample(0.25, Vec3(1, 2, 3), Eigen::Quaterniond(2.0, 0.0, 0.0, 0.0))});
  EXPECT_EQ(one.at(-1.0).position_m, Vec3(1, 2, 3));
  EXPECT_EQ(one.at(7.0).position_m, Vec3(1, 2, 3));
  EXPECT_EQ(one.samples()[0].orientation.w(), 1.0);  // normalised from (2, 0, 0, 0)
}

// ---------------------------------------------------------------------------------------------
// Files

TEST(TrajectoryFiles, CsvAndJsonGiveTheSameTrajectory) {
  const auto csv =
      write_file("same.csv",
                 "# a comment line, then the header\n"
                 "time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons\n"
                 "0,0.001,-0.002,0.1,1,0,0,0,0\n"
                 "\n"
                 "0.0105,0.0015,-0.0025,0.099,0.9238795325112867,0,0,0.3826834323650898,1\n"
                 " 0.02 , 0.003 , 0.25 , 0.2 , 0.7071067811865476 , 0 , 0.7071067811865476 , 0 , 3\r\n");
  const auto json = write_file("same.json", R"({
    "description": "the same three samples",
    "samples": [
      {"time_s": 0, "position_m": [0.001, -0.002, 0.1], "orientation_wxyz": [1, 0, 0, 0], "buttons": 0},
      {"time_s": 0.0105, "position_m": [0.0015, -0.0025, 0.099],
       "orientation_wxyz": [0.9238795325112867, 0, 0, 0.3826834323650898], "buttons": 1},
      {"time_s": 0.02, "position_m": [0.003, 0.25, 0.2], "orientation_wxyz": [0.7071067811865476, 0, 0.7071067811865476, 0],
       "buttons": 3}
    ]})");
  const Trajectory a = read_trajectory(csv), b = read_trajectory(json);
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_TRUE(same_bits(a.samples()[i], b.samples()[i])) << "sample " << i;
  for (double t = -0.01; t < 0.03; t += 0.0013) EXPECT_TRUE(same_bits(a.at(t), b.at(t))) << "t = " << t;
  EXPECT_EQ(a.samples()[2].buttons, 3u);
}

TEST(TrajectoryFiles, OptionalColumnsDefaultToIdentityAndNoButtons) {
  const Trajectory pos_only =
      read_trajectory(write_file("pos.csv", "time_s,x_m,y_m,z_m\n0,1,2,3\n1,2,3,4\n"));
  EXPECT_EQ(pos_only.samples()[1].orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(pos_only.samples()[1].buttons, 0u);
  const Trajectory with_buttons =
      read_trajectory(write_file("btn.CSV", "time_s,x_m,y_m,z_m,buttons\n0,1,2,3,7\n"));
  EXPECT_EQ(with_buttons.samples()[0].buttons, 7u);
  const Trajectory json =
      read_trajectory(write_file("pos.json", R"({"samples": [{"time_s": 0, "position_m": [1, 2, 3]}]})"));
  EXPECT_EQ(json.samples()[0].orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
}

TEST(TrajectoryFiles, WriteReadRoundTripIsBitIdentical) {
  // Awkward doubles: non-terminating binary fractions, negative zero, extremes and a subnormal.
  const std::vector<double> xs = {
      0.1, 1.0 / 3.0, -0.0, 1e-300, 5e-324, -1.7976931348623157e308, 2.0 / 3.0 * 1e-3};
  std::vector<DevicePose> samples;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double t = 0.001 * static_cast<double>(i) + 1.0 / 7.0;
    samples.push_back(sample(
        t, Vec3(xs[i], xs[(i + 1) % xs.size()], xs[(i + 2) % xs.size()]),
        Eigen::Quaterniond(Eigen::AngleAxisd(0.1 + static_cast<double>(i), Vec3(1, 2, 3).normalized())),
        static_cast<std::uint32_t>(i) * 0x10001u));
  }
  samples.back().buttons = std::numeric_limits<std::uint32_t>::max();
  const Trajectory tr(samples);
  const auto file = scratch() / "roundtrip.csv";
  write_trajectory_csv(tr, file);
  const Trajectory back = read_trajectory(file);
  ASSERT_EQ(back.size(), tr.size());
  for (std::size_t i = 0; i < tr.size(); ++i)
    EXPECT_TRUE(same_bits(back.samples()[i], tr.samples()[i])) << "sample " << i;
}

// ---------------------------------------------------------------------------------------------
// Bad files: one line, naming the file and the line (CSV) or the key (JSON)

TEST(TrajectoryErrors, MissingEmptyAndUnsupportedFiles) {
  const auto missing = scratch() / "no-such-file.csv";
  expect_message(read_error(missing), missing, {"cannot open"});
  const auto missing_json = scratch() / "no-such-file.json";
  expect_message(read_error(missing_json), missing_json, {"cannot open"});
  const auto empty = write_file("empty.csv", "");
  expect_message(read_error(empty), empty, {"empty", "time_s,x_m,y_m,z_m"});
  const auto comments_only = write_file("comments.csv", "# nothing here\n\n");
  expect_message(read_error(comments_only), comments_only, {"empty"});
  const auto header_only = write_file("header-only.csv", "time_s,x_m,y_m,z_m\n");
  expect_message(read_error(header_only), header_only, {"no samples"});
  const auto txt = write_file("traj.txt", "time_s,x_m,y_m,z_m\n0,0,0,0\n");
  expect_message(read_error(txt), txt, {"unsupported", "'.txt'", ".csv, .json"});
}

TEST(TrajectoryErrors, BadHeader) {
  const auto f = write_file("bad-header.csv", "time,x,y,z\n0,0,0,0\n");
  expect_message(read_error(f), f, {"line 1:", "header", "time_s,x_m,y_m,z_m[,qw,qx,qy,qz][,buttons]"});
  const auto partial_quat = write_file("partial-quat.csv", "time_s,x_m,y_m,z_m,qw,qx\n0,0,0,0,1,0\n");
  expect_message(read_error(partial_quat), partial_quat, {"line 1:", "header"});
  const auto reordered =
      write_file("reordered.csv", "# first comes a comment\ntime_s,y_m,x_m,z_m\n0,0,0,0\n");
  expect_message(read_error(reordered), reordered, {"line 2:", "header"});
}

TEST(TrajectoryErrors, MalformedRows) {
  const auto short_row = write_file("short-row.csv", "time_s,x_m,y_m,z_m\n0,0,0,0\n0.1,0,0\n");
  expect_message(read_error(short_row), short_row, {"line 3:", "expected 4", "found 3"});
  const auto long_row = write_file("long-row.csv", "time_s,x_m,y_m,z_m\n0,0,0,0,5\n");
  expect_message(read_error(long_row), long_row, {"line 2:", "expected 4", "found 5"});
  const auto text = write_file("text.csv", "time_s,x_m,y_m,z_m\n0,0,0,0\n\n0.1,abc,0,0\n");
  expect_message(read_error(text), text, {"line 4:", "'x_m'", "'abc'", "not a number"});
  const auto blank_cell = write_file("blank-cell.csv", "time_s,x_m,y_m,z_m\n0,0,,0\n");
  expect_message(read_error(blank_cell), blank_cell, {"line 2:", "'y_m'", "not a number"});
  const auto trailing = write_file("trailing.csv", "time_s,x_m,y_m,z_m\n0,0,0,1mm\n");
  expect_message(read_error(trailing), trailing, {"line 2:", "'z_m'", "'1mm'"});
  const auto buttons = write_file("buttons.csv", "time_s,x_m,y_m,z_m,buttons\n0,0,0,0,1.5\n");
  expect_message(read_error(buttons), buttons, {"line 2:", "'buttons'", "integer"});
  const auto negative_buttons = write_file("neg-buttons.csv", "time_s,x_m,y_m,z_m,buttons\n0,0,0,0,-1\n");
  expect_message(read_error(negative_buttons), negative_buttons, {"line 2:", "'buttons'"});
}

TEST(TrajectoryErrors, NonFiniteValues) {
  for (const std::string v : {"nan", "NaN", "inf", "-inf", "1e999"}) {
    const auto f = write_file("nonfinite.csv",
                              "time_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,0,0,0," + v + ",0,0,0\n");
    expect_message(read_error(f), f, {"line 3:", "'qw'", "not finite"});
  }
  const auto nan_time = write_file("nan-time.csv", "time_s,x_m,y_m,z_m\nnan,0,0,0\n");
  expect_message(read_error(nan_time), nan_time, {"line 2:", "'time_s'", "not finite"});
}

TEST(TrajectoryErrors, NonIncreasingTime) {
  const auto equal = write_file("equal-time.csv", "time_s,x_m,y_m,z_m\n0,0,0,0\n0.001,0,0,0\n0.001,1,0,0\n");
  expect_message(read_error(equal), equal, {"line 4:", "not greater than", "strictly increase"});
  const auto backwards = write_file("backwards.csv", "time_s,x_m,y_m,z_m\n# c\n0.5,0,0,0\n0.25,0,0,0\n");
  expect_message(read_error(backwards), backwards, {"line 4:", "0.25", "0.5", "strictly increase"});
}

TEST(TrajectoryErrors, ZeroQuaternion) {
  const auto f =
      write_file("zero-quat.csv", "time_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,0,0,0,0,0,0,0\n");
  expect_message(read_error(f), f, {"line 3:", "zero norm"});
}

TEST(TrajectoryErrors, JsonFilesNameTheKey) {
  const auto invalid = write_file("invalid.json", "{\"samples\": [");
  expect_message(read_error(invalid), invalid, {"not valid JSON"});
  const auto no_samples = write_file("no-samples.json", "{\"sample\": []}");
  expect_message(read_error(no_samples), no_samples, {"'samples'", "missing"});
  const auto empty = write_file("empty-samples.json", "{\"samples\": []}");
  expect_message(read_error(empty), empty, {"no samples"});
  const auto backwards = write_file("backwards.json", R"({"samples": [{"time_s": 1, "position_m": [0, 0, 0]},
                                                                       {"time_s": 1, "position_m": [0, 0, 0]}]})");
  expect_message(read_error(backwards), backwards, {"'samples.1.time_s'", "strictly increase"});
  const auto zero_q = write_file(
      "zero-q.json",
      R"({"samples": [{"time_s": 0, "position_m": [0, 0, 0], "orientation_wxyz": [0, 0, 0, 0]}]})");
  expect_message(read_error(zero_q), zero_q, {"'samples.0.orientation_wxyz'", "zero norm"});
  const auto short_q =
      write_file("short-q.json",
                 R"({"samples": [{"time_s": 0, "position_m": [0, 0, 0], "orientation_wxyz": [1, 0, 0]}]})");
  expect_message(read_error(short_q), short_q, {"'samples.0.orientation_wxyz'", "4 finite numbers"});
  const auto bad_pos =
      write_file("bad-pos.json", R"({"samples": [{"time_s": 0, "position_m": [0, "a", 0]}]})");
  expect_message(read_error(bad_pos), bad_pos, {"'samples.0.position_m'"});
  const auto huge = write_file("huge.json", R"({"samples": [{"time_s": 1e999, "position_m": [0, 0, 0]}]})");
  expect_message(read_error(huge), huge, {"not valid JSON", "overflow"});
  const auto typo =
      write_file("typo.json", R"({"samples": [{"time_s": 0, "position_m": [0, 0, 0], "button": 1}]})");
  expect_message(read_error(typo), typo, {"'samples.0.button'", "unknown key"});
  const auto buttons = write_file("bad-buttons.json",
                                  R"({"samples": [{"time_s": 0, "position_m": [0, 0, 0], "buttons": -2}]})");
  expect_message(read_error(buttons), buttons, {"'samples.0.buttons'", "integer"});
}

// ---------------------------------------------------------------------------------------------
// Scripted device and session recording

TEST(DeviceScripted, PlaysTheTrajectoryAndRecordsEveryForce) {
  ScriptedDevice dev(Trajectory({sample(0.0, Vec3::Zero()), sample(1.0, Vec3(0.01, 0, 0))}));
  EXPECT_EQ(dev.name(), "scripted");
  EXPECT_EQ(dev.limits().max_continuous_force_n, 0.88);
  EXPECT_EQ(dev.limits().max_peak_force_n, 3.3);
  EXPECT_NEAR(dev.pose(0.25).position_m.x(), 0.0025, 1e-15);
  EXPECT_EQ(dev.last_sent_force(), Vec3::Zero());

  dev.send_force(Vec3(0.1, 0.2, 0.3), 0.001);
  dev.send_force(Vec3(-0.5, 0.0, 0.0), 0.002);
  // A controller bug must stay visible: the scripted device stores exactly what it receives.
  dev.send_force(Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0), 0.003);
  ASSERT_EQ(dev.sent_forces().size(), 3u);
  EXPECT_EQ(dev.sent_forces()[0].time_s, 0.001);
  EXPECT_EQ(dev.sent_forces()[0].force_n, Vec3(0.1, 0.2, 0.3));
  EXPECT_EQ(dev.sent_forces()[1].force_n, Vec3(-0.5, 0.0, 0.0));
  EXPECT_TRUE(std::isnan(dev.sent_forces()[2].force_n.x()));
  EXPECT_TRUE(std::isnan(dev.last_sent_force().x()));
  // The log was reserved for about 1 kHz over the trajectory, so these calls did not allocate.
  EXPECT_GE(dev.sent_forces().capacity(), 1000u);
}

/// A stand-in for a controller: a spring to an anchor plus the pose's buttons as a force offset.
Vec3 toy_controller(const DevicePose& p) {
  return -250.0 * (p.position_m - Vec3(0.001, 0.0, 0.0)) +
         1e-3 * static_cast<double>(p.buttons) * Vec3::UnitZ() + 0.01 * (p.orientation * Vec3::UnitX());
}

/// Runs the toy controller on `dev` for `ticks` ticks of 1 ms, recording every tick.
SessionRecording run_session(Device& dev, int ticks, double t0) {
  SessionRecording rec(static_cast<std::size_t>(ticks));
  for (int k = 0; k < ticks; ++k) {
    const DevicePose p = dev.pose(t0 + 1e-3 * k);
    const Vec3 f = toy_controller(p);
    dev.send_force(f, p.time_s);
    rec.record(p, f);
  }
  return rec;
}

TEST(RecordingRoundTrip, FileReadsBackBitIdentical) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SessionRecording rec(500);
  const std::size_t capacity = rec.capacity();
  double t = 1.0 / 3.0;
  for (int k = 0; k < 500; ++k) {
    t += 1e-3 * (1.0 + 0.1 * u(rng));  // a jittery clock, like a real loop
    const Vec3 p = 0.05 * Vec3(u(rng), u(rng), u(rng));
    const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    rec.record(DevicePose{t, p, q, static_cast<std::uint32_t>(k % 4)}, 3.3 * Vec3(u(rng), u(rng), u(rng)));
  }
  EXPECT_EQ(rec.capacity(), capacity);  // reserved: no allocation while recording

  const auto file = scratch() / "recording.csv";
  rec.write_csv(file);
  const RecordedSession back = read_session_recording(file);
  ASSERT_EQ(back.trajectory.size(), rec.size());
  ASSERT_EQ(back.forces.size(), rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    EXPECT_TRUE(same_bits(back.trajectory.samples()[i], rec.ticks()[i].pose)) << "tick " << i;
    EXPECT_TRUE(same_bits(back.forces[i].time_s, rec.ticks()[i].pose.time_s));
    for (int a = 0; a < 3; ++a)
      EXPECT_TRUE(same_bits(back.forces[i].force_n[a], rec.ticks()[i].force_n[a])) << "tick " << i;
  }
  // A recording is also a plain trajectory file (the force columns are ignored).
  EXPECT_TRUE(same_bits(read_trajectory(file).samples()[7], rec.ticks()[7].pose));
  EXPECT_EQ(rec.forces().size(), rec.size());
}

TEST(RecordingRoundTrip, ReplayReproducesTheSessionExactly) {
  // Record a session driven by an interpolated trajectory, replay its file and compare bit for bit.
  ScriptedDevice live(Trajectory({sample(0.0, Vec3(0, 0, 0), about_z(0.0), 0),
                                  sample(0.0733, Vec3(0.003, -0.001, 0.002), about_z(1.1), 1),
                                  sample(0.2, Vec3(0.0, 0.004, 0.0), about_z(-0.4), 2)}));
  const SessionRecording rec = run_session(live, 200, 0.0);
  const auto file = scratch() / "session.csv";
  rec.write_csv(file);

  const RecordedSession recorded = read_session_recording(file);
  ScriptedDevice replay(recorded.trajectory);
  const SessionRecording again = run_session(replay, 200, 0.0);
  ASSERT_EQ(again.size(), rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    EXPECT_TRUE(same_bits(again.ticks()[i].pose, rec.ticks()[i].pose)) << "tick " << i;
    for (int a = 0; a < 3; ++a) {
      EXPECT_TRUE(same_bits(again.ticks()[i].force_n[a], recorded.forces[i].force_n[a])) << "tick " << i;
      EXPECT_TRUE(same_bits(replay.sent_forces()[i].force_n[a], live.sent_forces()[i].force_n[a]))
          << "tick " << i;
    }
  }
}

TEST(RecordingRoundTrip, BadRecordingFiles) {
  const auto no_forces =
      write_file("no-forces.csv", "time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons\n0,0,0,0,1,0,0,0,0\n");
  try {
    read_session_recording(no_forces);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    expect_message(e.what(), no_forces, {"force columns", "fx_n,fy_n,fz_n"});
  }
  const auto nan_force = write_file(
      "nan-force.csv", "time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons,fx_n,fy_n,fz_n\n0,0,0,0,1,0,0,0,0,0,nan,0\n");
  try {
    read_session_recording(nan_force);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    expect_message(e.what(), nan_force, {"line 2:", "'fy_n'", "not finite"});
  }
  SessionRecording repeated;
  repeated.record(sample(0.0, Vec3::Zero()), Vec3::Zero());
  repeated.record(sample(0.0, Vec3::Zero()), Vec3::Zero());
  EXPECT_THROW(repeated.trajectory(), InputError);
  const auto unwritable = scratch() / "no-such-dir" / "rec.csv";
  try {
    repeated.write_csv(unwritable);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    expect_message(e.what(), unwritable, {"cannot write"});
  }
}

// ---------------------------------------------------------------------------------------------
// Mouse and keyboard

TEST(MouseMapping, CursorMovesInTheViewPlaneWithTheGain) {
  MouseKeyboardSettings s;  // right = x, up = y, forward = -z
  s.gain_m_per_pixel = 2e-4;
  MouseKeyboardDevice dev(s);
  EXPECT_EQ(dev.name(), "mouse_keyboard");
  EXPECT_EQ(dev.pose(0.0).position_m, Vec3::Zero());
  EXPECT_NEAR(dev.pose(0.0).orientation.angularDistance(Eigen::Quaterniond::Identity()), 0.0, 1e-15);
  dev.move_cursor(100.0, 0.0);
  EXPECT_NEAR((dev.pose(0.001).position_m - Vec3(0.02, 0.0, 0.0)).norm(), 0.0, 1e-15);
  dev.move_cursor(0.0, 50.0);  // downwards on screen
  EXPECT_NEAR((dev.pose(0.002).position_m - Vec3(0.02, -0.01, 0.0)).norm(), 0.0, 1e-15);

  // A camera looking along -x from the side: right = +y, up = +z.
  MouseKeyboardSettings side;
  side.view = {Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitX()};
  side.limits.workspace_center_m = Vec3(0.1, 0.2, 0.3);
  MouseKeyboardDevice dev2(side);
  dev2.move_cursor(10.0, -20.0);
  const DevicePose p = dev2.pose(0.0);
  EXPECT_NEAR((p.position_m - Vec3(0.1, 0.201, 0.302)).norm(), 0.0, 1e-15);
  // The tool points along the view direction (its local -z axis).
  EXPECT_NEAR((p.orientation * (-Vec3::UnitZ()) - (-Vec3::UnitX())).norm(), 0.0, 1e-15);
  EXPECT_NEAR((p.orientation * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, 1e-15);
}

TEST(MouseMapping, ScrollAndKeysInsertAlongForward) {
  MouseKeyboardSettings s;
  s.view = {Vec3::UnitX(), Vec3::UnitZ(), Vec3::UnitY()};  // looking along +y, z up
  MouseKeyboardDevice dev(s);
  dev.scroll(3.0);
  EXPECT_NEAR((dev.pose(0.0).position_m - Vec3(0.0, 0.003, 0.0)).norm(), 0.0, 1e-15);
  dev.scroll(-1.0);
  EXPECT_NEAR((dev.pose(0.0).position_m - Vec3(0.0, 0.002, 0.0)).norm(), 0.0, 1e-15);

  const double v = s.key_speed_m_per_s;
  dev.set_key(ToolKey::insert, true);
  EXPECT_NEAR(dev.pose(1.0).position_m.y(), 0.002, 1e-15);  // motion starts at the first pose after the press
  EXPECT_NEAR(dev.pose(1.05).position_m.y(), 0.002 + 0.05 * v, 1e-15);
  dev.set_key(ToolKey::insert, false);
  EXPECT_NEAR(dev.pose(1.1).position_m.y(), 0.002 + 0.05 * v, 1e-15);  // released: no motion
  dev.set_key(ToolKey::retract, true);
  dev.pose(1.2);
  EXPECT_NEAR(dev.pose(1.225).position_m.y(), 0.002 + 0.025 * v, 1e-15);
  // After a long pause only 0.1 s is integrated: no jump.
  EXPECT_NEAR(dev.pose(60.0).position_m.y(), 0.002 - 0.075 * v, 1e-15);
  dev.reset();
  EXPECT_EQ(dev.pose(61.0).position_m, Vec3::Zero());
}

TEST(MouseMapping, ClampedToTheWorkspaceSphere) {
  MouseKeyboardSettings s;
  s.limits.workspace_center_m = Vec3(0.0, 0.0, -0.05);
  s.limits.workspace_radius_m = 0.03;
  MouseKeyboardDevice dev(s);
  dev.move_cursor(1e6, 0.0);
  Vec3 p = dev.pose(0.0).position_m;
  EXPECT_NEAR((p - s.limits.workspace_center_m).norm(), 0.03, 1e-15);
  EXPECT_NEAR(p.x(), 0.03, 1e-15);
  // The stored position is clamped too: moving back responds at once.
  dev.move_cursor(-100.0, 0.0);
  EXPECT_NEAR(dev.pose(0.0).position_m.x(), 0.02, 1e-15);
  dev.scroll(1e6);
  p = dev.pose(0.0).position_m;
  EXPECT_NEAR((p - s.limits.workspace_center_m).norm(), 0.03, 1e-15);
  dev.set_key(ToolKey::insert, true);
  dev.pose(1.0);
  EXPECT_LE((dev.pose(1.1).position_m - s.limits.workspace_center_m).norm(), 0.03 + 1e-15);
}

TEST(MouseMapping, ButtonsForceAndViewChecks) {
  MouseKeyboardDevice dev;
  dev.set_button(0, true);
  dev.set_button(2, true);
  dev.set_button(40, true);  // ignored
  EXPECT_EQ(dev.pose(0.0).buttons, 5u);
  dev.set_button(0, false);
  EXPECT_EQ(dev.pose(0.0).buttons, 4u);
  dev.send_force(Vec3(0.1, -0.2, 0.3), 0.0);
  EXPECT_EQ(dev.last_sent_force(), Vec3(0.1, -0.2, 0.3));

  // Slightly skewed axes are re-orthonormalised; degenerate or left-handed frames are refused.
  dev.set_view({Vec3(1.0, 0.01, 0.0), Vec3::UnitY(), -Vec3::UnitZ()});
  EXPECT_NEAR(dev.pose(0.0).orientation.norm(), 1.0, 1e-15);
  EXPECT_THROW(dev.set_view({-Vec3::UnitZ(), Vec3::UnitY(), -Vec3::UnitZ()}), std::invalid_argument);
  EXPECT_THROW(dev.set_view({Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ()}), std::invalid_argument);
  EXPECT_THROW(dev.set_view({Vec3::UnitX(), Vec3::UnitY(), Vec3::Zero()}), std::invalid_argument);
}

TEST(MouseMapping, AdvanceAlongTheToolAxisTwistAndSteer) {
  // A tool given its own orientation: pointing along -y (as a catheter pressed down onto a vessel), seen by
  // a camera looking along -z. Insertion follows the tool, not the view; camera moves leave it alone.
  MouseKeyboardSettings s;
  s.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(-0.5 * std::numbers::pi, Vec3::UnitX()));  // -z -> -y
  MouseKeyboardDevice dev(s);
  const auto axis = [&](double t) { return Vec3(dev.pose(t).orientation * (-Vec3::UnitZ())); };
  EXPECT_NEAR((axis(0.0) - (-Vec3::UnitY())).norm(), 0.0, 1e-15);
  dev.scroll(2.0);
  EXPECT_NEAR((dev.pose(0.0).position_m - Vec3(0.0, -0.002, 0.0)).norm(), 0.0, 1e-15);
  dev.set_view({Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitX()});
  EXPECT_NEAR((axis(0.0) - (-Vec3::UnitY())).norm(), 0.0, 1e-15);
  dev.set_view({});

  // Twist: about the axis at key_twist, clockwise seen from behind (right-hand rule about the axis).
  const Vec3 side0 = dev.pose(1.0).orientation * Vec3::UnitX();
  dev.set_key(ToolKey::twist_right, true);
  dev.pose(1.0);
  const DevicePose twisted = dev.pose(1.1);
  dev.set_key(ToolKey::twist_right, false);
  const double angle = 0.1 * s.key_twist_rad_per_s;
  EXPECT_NEAR((twisted.orientation * Vec3::UnitX() - Eigen::AngleAxisd(angle, -Vec3::UnitY()) * side0).norm(),
              0.0, 1e-12);
  EXPECT_NEAR((twisted.orientation * (-Vec3::UnitZ()) - (-Vec3::UnitY())).norm(), 0.0,
              1e-12);                                                             // axis unchanged
  EXPECT_NEAR((twisted.position_m - Vec3(0.0, -0.002, 0.0)).norm(), 0.0, 1e-15);  // tool point too

  // Steer: a drag to the right turns the axis towards the view's right (+x) about the tool point.
  dev.steer(100.0, 0.0);
  const Vec3 a = axis(2.0);
  EXPECT_NEAR(a.x(), std::sin(100.0 * s.steer_rad_per_pixel), 1e-12);
  EXPECT_NEAR(a.y(), -std::cos(100.0 * s.steer_rad_per_pixel), 1e-12);
  EXPECT_NEAR((dev.pose(2.0).position_m - Vec3(0.0, -0.002, 0.0)).norm(), 0.0, 1e-15);
  dev.reset();
  EXPECT_NEAR((axis(3.0) - (-Vec3::UnitY())).norm(), 0.0, 1e-15);

  // The default tool (no orientation given) follows the view until it is steered.
  MouseKeyboardDevice follower;
  follower.set_view({Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitX()});
  EXPECT_NEAR((follower.pose(0.0).orientation * (-Vec3::UnitZ()) - (-Vec3::UnitX())).norm(), 0.0, 1e-15);
  follower.steer(0.0, -50.0);  // upwards
  const Vec3 up = follower.pose(0.0).orientation * (-Vec3::UnitZ());
  EXPECT_GT(up.z(), 0.0);
  follower.set_view({});
  EXPECT_NEAR((follower.pose(0.0).orientation * (-Vec3::UnitZ()) - up).norm(), 0.0, 1e-15);
  MouseKeyboardSettings zero;
  zero.orientation = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_THROW(MouseKeyboardDevice{zero}, std::invalid_argument);
}

TEST(MouseMapping, InputFromAnotherThreadIsNeverLost) {
  // The UI thread moves the cursor while this (haptic) thread polls; every pixel arrives eventually.
  MouseKeyboardSettings s;
  s.gain_m_per_pixel = 1e-6;
  MouseKeyboardDevice dev(s);
  std::atomic<bool> done{false};
  std::thread ui([&] {
    for (int i = 0; i < 2000; ++i) dev.move_cursor(1.0, 0.0);
    done = true;
  });
  int polls = 0;
  while (!done.load()) {
    const double x = dev.pose(1e-3 * polls++).position_m.x();
    ASSERT_TRUE(x >= 0.0 && x <= 2000e-6 + 1e-12);
  }
  ui.join();
  EXPECT_NEAR(dev.pose(1.0).position_m.x(), 2000e-6, 1e-12);
}

TEST(DeviceLimitsDefaults, PhantomOmniClass) {
  const DeviceLimits l;
  EXPECT_EQ(l.max_continuous_force_n, 0.88);
  EXPECT_EQ(l.max_peak_force_n, 3.3);
  EXPECT_GT(l.workspace_radius_m, 0.0);
  EXPECT_GT(l.max_stiffness_n_per_m, 0.0);
}

}  // namespace
