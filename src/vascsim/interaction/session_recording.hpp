#pragma once
// Recording of a device session: per haptic tick, the pose read from the device and the force sent to
// it. The recording file replays the session: its poses form a Trajectory for the ScriptedDevice. A
// replay queried at the recorded times returns the recorded poses bit for bit. Its forces are the
// reference to compare a replay against. File format: docs/devices.md.
//
// Threads: one thread (the haptic thread) writes a recording through record(). Everything else
// (ticks(), write_csv(), trajectory()) may run only after that thread has stopped or been joined.
// There is no internal locking.

#include <cstddef>
#include <filesystem>
#include <vector>

#include "vascsim/interaction/device.hpp"
#include "vascsim/interaction/trajectory.hpp"

namespace vascsim {

/// One haptic tick: the pose the loop read and the force it sent in that tick; and, for analysis (not part of
/// the replay file), where the tool (the coupling's proxy) was and the tissue's force on it at that tick.
struct RecordedTick {
  DevicePose pose;
  Vec3 force_n = Vec3::Zero();
  Vec3 tool_m = Vec3::Zero();
  Vec3 tissue_force_n = Vec3::Zero();
};

class SessionRecording {
 public:
  SessionRecording() = default;
  /// Reserves `ticks` entries (e.g. duration_s x 1000 for a 1 kHz loop) so record() never allocates.
  explicit SessionRecording(std::size_t ticks) { reserve(ticks); }

  void reserve(std::size_t ticks) { ticks_.reserve(ticks); }
  /// Appends one tick. It allocates nothing while size() < capacity(). Past that point the buffer
  /// grows by doubling: this still works, but costs one copy of the whole buffer.
  void record(const DevicePose& pose, const Vec3& sent_force_n, const Vec3& tool_m = Vec3::Zero(),
              const Vec3& tissue_force_n = Vec3::Zero()) {
    ticks_.push_back({pose, sent_force_n, tool_m, tissue_force_n});
  }
  void clear() { ticks_.clear(); }

  std::size_t size() const { return ticks_.size(); }
  std::size_t capacity() const { return ticks_.capacity(); }
  bool empty() const { return ticks_.empty(); }
  const std::vector<RecordedTick>& ticks() const { return ticks_; }

  /// The recorded poses as a Trajectory. Throws InputError if the tick times do not strictly
  /// increase.
  Trajectory trajectory() const;
  /// The recorded forces, with the time of each tick.
  std::vector<ForceSample> forces() const;
  /// Writes time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons,fx_n,fy_n,fz_n with %.17g. The file reads back
  /// to the same doubles.
  void write_csv(const std::filesystem::path& file) const;
  /// Writes the per-tick analysis table (haptic_ticks.csv): time_s, the device position (m), the tool
  /// position (m), the tissue's force on the tool at that tick (N) and the force sent to the device (N),
  /// %.17g.
  void write_ticks_csv(const std::filesystem::path& file) const;

 private:
  std::vector<RecordedTick> ticks_;
};

/// A recording read back from its file.
struct RecordedSession {
  Trajectory trajectory;            ///< for replay with ScriptedDevice
  std::vector<ForceSample> forces;  ///< the forces sent during the recorded run, one per tick
};

/// Reads a file written by SessionRecording::write_csv. The force columns are required. Errors are
/// the trajectory CSV errors: "<file>: line <n>: ...".
RecordedSession read_session_recording(const std::filesystem::path& file);

}  // namespace vascsim
