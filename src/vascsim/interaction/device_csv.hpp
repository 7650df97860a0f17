#pragma once
// The CSV layout shared by trajectory files and session recordings (docs/devices.md): a header
// `time_s,x_m,y_m,z_m[,qw,qx,qy,qz][,buttons][,fx_n,fy_n,fz_n]`, then one row of numbers per sample.
// One parser serves both, so that a recording is also a trajectory and the errors read the same.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "vascsim/interaction/device.hpp"
#include "vascsim/interaction/trajectory.hpp"

namespace vascsim::device_csv {

/// The contents of a device CSV file. Syntax and finiteness are checked row by row. The ordering and
/// quaternion rules are left to Trajectory, which reports them through locator().
struct Table {
  std::vector<DevicePose> poses;  ///< orientation as read (not normalised), identity if absent
  std::vector<int> lines;         ///< 1-based line number of each pose
  std::vector<Vec3> forces_n;     ///< one per pose if has_forces, else empty
  bool has_orientation = false;
  bool has_buttons = false;
  bool has_forces = false;
};

/// Reads and checks `file`. Throws InputError "<file>: line <n>: <problem>; <what is allowed>".
Table read(const std::filesystem::path& file);

/// Builds the Trajectory of a table, so that its errors name the file and the line.
Trajectory to_trajectory(const Table& table, const std::filesystem::path& file);

/// Writes a device CSV with every column, each double printed with %.17g so that it reads back
/// bit-identically. Rows are streamed, so a long recording is never held twice in memory.
class Writer {
 public:
  /// Opens `file` and writes the header, with the force columns if `with_forces`. Throws InputError
  /// "<file>: cannot write ..." if the file cannot be created.
  Writer(const std::filesystem::path& file, bool with_forces);
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// One row. Pass `force_n` exactly when the writer was opened with forces.
  void row(const DevicePose& pose, const Vec3* force_n);
  /// Flushes and closes; throws InputError if anything failed to reach the disk.
  void close();

 private:
  std::filesystem::path file_;
  std::FILE* out_ = nullptr;
  bool with_forces_ = false;
};

}  // namespace vascsim::device_csv
