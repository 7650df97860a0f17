#include "vascsim/interaction/session_recording.hpp"

#include <fmt/format.h>

#include <cstdio>

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

void SessionRecording::write_ticks_csv(const std::filesystem::path& file) const {
  std::FILE* f = std::fopen(file.string().c_str(), "w");
  if (!f) throw InputError(fmt::format("{}: cannot write the tick table", file.string()));
  std::fputs(
      "time_s,device_x_m,device_y_m,device_z_m,tool_x_m,tool_y_m,tool_z_m,tissue_fx_n,tissue_fy_n,"
      "tissue_fz_n,sent_fx_n,sent_fy_n,sent_fz_n\n",
      f);
  for (const auto& t : ticks_) {
    const Vec3& d = t.pose.position_m;
    fmt::print(f,
               "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:."
               "17g},{:.17g}\n",
               t.pose.time_s, d.x(), d.y(), d.z(), t.tool_m.x(), t.tool_m.y(), t.tool_m.z(),
               t.tissue_force_n.x(), t.tissue_force_n.y(), t.tissue_force_n.z(), t.force_n.x(), t.force_n.y(),
               t.force_n.z());
  }
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok)
    throw InputError(fmt::format("{}: writing the tick table failed", file.string()));
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
