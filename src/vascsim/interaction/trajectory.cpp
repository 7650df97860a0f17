#include "vascsim/interaction/trajectory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "vascsim/core/error.hpp"
#include "vascsim/core/json_file.hpp"
#include "vascsim/core/json_reader.hpp"
#include "vascsim/interaction/device_csv.hpp"

namespace vascsim {

namespace {

// Below this norm a quaternion is taken as a mistake, not as a rotation.
constexpr double kMinQuaternionNorm = 1e-9;
// A quaternion this close to unit length is kept bit for bit: renormalising it could change the last
// bit and break exact replay of a recording.
constexpr double kUnitTolerance = 1e-12;

}  // namespace

Trajectory::Trajectory(std::vector<DevicePose> samples, const std::string& source, const Locator& where)
    : samples_(std::move(samples)) {
  const auto at = [&](std::size_t i, std::string_view field) {
    return where ? where(i, field) : fmt::format("{}: sample {} ({})", source, i, field);
  };
  if (samples_.empty())
    throw InputError(fmt::format("{}: no samples; a trajectory needs at least one sample", source));
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    DevicePose& p = samples_[i];
    if (!std::isfinite(p.time_s))
      throw InputError(
          fmt::format("{}: time_s is not finite; every value must be a finite number", at(i, "time_s")));
    if (!p.position_m.allFinite())
      throw InputError(fmt::format("{}: position is not finite; every value must be a finite number",
                                   at(i, "position_m")));
    auto& q = p.orientation;
    if (!q.coeffs().allFinite())
      throw InputError(fmt::format("{}: orientation is not finite; every value must be a finite number",
                                   at(i, "orientation_wxyz")));
    // The norm of the coefficients scaled by the largest one: no overflow for (1e300, 1e300, 0, 0).
    const double largest = q.coeffs().cwiseAbs().maxCoeff();
    const double n = largest > 0.0 ? largest * (q.coeffs() / largest).norm() : 0.0;
    if (n < kMinQuaternionNorm)
      throw InputError(
          fmt::format("{}: orientation quaternion (qw,qx,qy,qz) = ({}, {}, {}, {}) has zero norm; a rotation "
                      "needs a non-zero quaternion "
                      "(identity: 1,0,0,0)",
                      at(i, "orientation_wxyz"), q.w(), q.x(), q.y(), q.z()));
    if (std::abs(n - 1.0) > kUnitTolerance) q.coeffs() = (q.coeffs() / largest).normalized();
    if (i > 0 && !(p.time_s > samples_[i - 1].time_s))
      throw InputError(fmt::format(
          "{}: time_s {} is not greater than the previous sample's {}; times must strictly increase",
          at(i, "time_s"), p.time_s, samples_[i - 1].time_s));
  }
}

DevicePose Trajectory::at(double time_s) const {
  // The first sample strictly later than time_s; the segment starts one before it.
  const auto later = std::upper_bound(samples_.begin(), samples_.end(), time_s,
                                      [](double t, const DevicePose& p) { return t < p.time_s; });
  DevicePose out;
  if (later == samples_.begin()) {
    out = samples_.front();  // clamped before the start
  } else {
    const DevicePose& a = *(later - 1);
    if (later == samples_.end() || time_s == a.time_s) {
      out = a;  // clamped after the end, or exactly on a sample: returned bit for bit
    } else {
      const DevicePose& b = *later;
      const double s = (time_s - a.time_s) / (b.time_s - a.time_s);
      out.position_m = (1.0 - s) * a.position_m + s * b.position_m;
      out.orientation = a.orientation.slerp(s, b.orientation);  // Eigen takes the shorter arc
      out.buttons = a.buttons;
    }
  }
  out.time_s = time_s;
  return out;
}

Trajectory read_trajectory(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".csv") return read_trajectory_csv(file);
  if (ext == ".json") return read_trajectory_json(file);
  throw InputError(fmt::format("{}: unsupported trajectory file extension '{}'; allowed: .csv, .json",
                               file.string(), ext));
}

Trajectory read_trajectory_csv(const std::filesystem::path& file) {
  return device_csv::to_trajectory(device_csv::read(file), file);
}

Trajectory read_trajectory_json(const std::filesystem::path& file) {
  const std::string name = file.string();
  const nlohmann::json doc =
      read_json_file(file, "the file", "expected a JSON trajectory {\"samples\": [...]}");

  JsonReader root(doc, "", name);
  root.string("description", "");  // free text for people; ignored
  auto rows = root.array_of_objects("samples", true);
  root.finish();

  constexpr double kBig = std::numeric_limits<double>::max();
  std::vector<DevicePose> poses;
  poses.reserve(rows.size());
  for (auto& r : rows) {
    DevicePose p;
    p.time_s = r.required_number("time_s", -kBig, kBig);
    p.position_m = r.required_vec3("position_m");
    if (const auto* q = r.raw("orientation_wxyz")) {
      const bool ok = q->is_array() && q->size() == 4 && std::all_of(q->begin(), q->end(), [](const auto& e) {
                        return e.is_number() && std::isfinite(e.template get<double>());
                      });
      if (!ok)
        r.fail("orientation_wxyz", "expected an array of 4 finite numbers [w, x, y, z] (a quaternion)");
      p.orientation = Eigen::Quaterniond((*q)[0].get<double>(), (*q)[1].get<double>(), (*q)[2].get<double>(),
                                         (*q)[3].get<double>());
    }
    if (const auto* b = r.raw("buttons")) {
      constexpr double kMax = std::numeric_limits<std::uint32_t>::max();
      const bool ok = b->is_number() && b->get<double>() >= 0.0 && b->get<double>() <= kMax &&
                      std::floor(b->get<double>()) == b->get<double>();
      if (!ok) r.fail("buttons", fmt::format("expected an integer in [0, {}] (a bit mask)", kMax));
      p.buttons = static_cast<std::uint32_t>(b->get<double>());
    }
    r.finish();
    poses.push_back(p);
  }
  return Trajectory(std::move(poses), name, [&](std::size_t i, std::string_view field) {
    return fmt::format("{}: key 'samples.{}.{}'", name, i, field);
  });
}

void write_trajectory_csv(const Trajectory& trajectory, const std::filesystem::path& file) {
  device_csv::Writer w(file, /*with_forces=*/false);
  for (const auto& p : trajectory.samples()) w.row(p, nullptr);
  w.close();
}

}  // namespace vascsim
