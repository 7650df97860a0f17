#include "vascsim/interaction/session_recording.hpp"

#include <fmt/format.h>

#include "vascsim/core/error.hpp"
#include "vascsim/interaction/device_csv.hpp"

namespace vascsim {

Trajectory SessionRecording::trajectory() const {
  std::vector<DevicePose> poses;
  poses.reserve(ticks_.size());
  for (const auto& t : ticks_) poses.push_back(t.pose);
  return Trajectory(std::move(poses), "session recording", [](std::size_t i, std::string_view field) {
    return fmt::format("session recording: tick {} ({})", i, field);
  });
}

std::vector<ForceSample> SessionRecording::forces() const {
  std::vector<ForceSample> out;
  out.reserve(ticks_.size());
  for (const auto& t : ticks_) out.push_back({t.pose.time_s, t.force_n});
  return out;
}

void SessionRecording::write_csv(const std::filesystem::path& file) const {
  device_csv::Writer w(file, /*with_forces=*/true);
  for (const auto& t : ticks_) w.row(t.pose, &t.force_n);
  w.close();
}

RecordedSession read_session_recording(const std::filesystem::path& file) {
  const auto table = device_csv::read(file);
  if (!table.has_forces)
    throw InputError(
        fmt::format("{}: the header has no force columns; a session recording has "
                    "time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons,fx_n,fy_n,fz_n",
                    file.string()));
  RecordedSession s{device_csv::to_trajectory(table, file), {}};
  s.forces.reserve(table.forces_n.size());
  for (std::size_t i = 0; i < table.forces_n.size(); ++i)
    s.forces.push_back({table.poses[i].time_s, table.forces_n[i]});
  return s;
}

}  // namespace vascsim
