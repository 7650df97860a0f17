#pragma once
// A device trajectory: time-stamped poses read from a CSV or JSON file and played back by the scripted
// device. The file formats are in docs/devices.md. Every reading problem is an InputError of one line,
// "<file>: line <n>: <what is wrong>; <what is allowed>" (CSV) or "<file>: key 'samples.<i>.<key>': ..."
// (JSON).

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "vascsim/interaction/device.hpp"

namespace vascsim {

/// Strictly time-ordered device samples with interpolation.
///
/// Between samples the position is interpolated linearly and the orientation by slerp (shortest arc).
/// The buttons come from the earlier sample. Before the first sample the first pose holds, and after
/// the last sample the last pose holds. At a sample time the sample is returned bit for bit, so a
/// recorded session replays exactly when it is queried at the recorded times.
class Trajectory {
 public:
  /// Names sample `index`'s `field` in an error message. Examples: "traj.csv: line 7" and
  /// "traj.json: key 'samples.5.time_s'".
  using Locator = std::function<std::string(std::size_t index, std::string_view field)>;

  /// An empty trajectory: at() must not be called on it.
  Trajectory() = default;
  /// Validates the samples. There must be at least one. Every value must be finite. Times must
  /// strictly increase. No quaternion may be zero. A quaternion whose norm differs from 1 by more
  /// than 1e-12 is normalised; within that tolerance it is kept as given, so a file written by
  /// write_trajectory_csv reads back bit-identically. Throws InputError. The message starts with
  /// where(i, field) when `where` is given, and otherwise with "<source>: sample <i> (<field>)".
  explicit Trajectory(std::vector<DevicePose> samples, const std::string& source = "trajectory",
                      const Locator& where = {});

  const std::vector<DevicePose>& samples() const { return samples_; }
  std::size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  double start_time_s() const { return samples_.front().time_s; }
  double end_time_s() const { return samples_.back().time_s; }

  /// The pose at `time_s`, with the interpolation described above. The result's time_s is the
  /// queried time. Costs O(log n), allocates nothing, and is safe to call from several threads.
  DevicePose at(double time_s) const;

 private:
  std::vector<DevicePose> samples_;
};

/// Reads a .csv or .json trajectory (chosen by the extension, case-insensitive). A session recording
/// (session_recording.hpp) is also a valid CSV trajectory: its force columns are ignored.
Trajectory read_trajectory(const std::filesystem::path& file);
Trajectory read_trajectory_csv(const std::filesystem::path& file);
Trajectory read_trajectory_json(const std::filesystem::path& file);

/// Writes every column (time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons) with 17 significant digits, which
/// is enough for the file to read back to the same doubles. Throws InputError if the file cannot be
/// written.
void write_trajectory_csv(const Trajectory& trajectory, const std::filesystem::path& file);

}  // namespace vascsim
