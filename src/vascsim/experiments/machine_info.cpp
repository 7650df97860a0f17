#include "vascsim/experiments/machine_info.hpp"

#include "vascsim/core/build_info.hpp"

#include <omp.h>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <thread>

namespace vascsim {

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      return colon == std::string::npos ? line : line.substr(line.find_first_not_of(' ', colon + 1));
    }
  return "unknown";
}

}  // namespace

double load_average_1min() {
  double l[1] = {-1.0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

nlohmann::json machine_info() {
  double l[3] = {-1.0, -1.0, -1.0};
  getloadavg(l, 3);
  const BuildInfo build = build_info();
  return {{"cpu_model", cpu_model()},
          {"hardware_concurrency", std::thread::hardware_concurrency()},
          {"omp_num_procs", omp_get_num_procs()},
          {"omp_max_threads", omp_get_max_threads()},
          {"load_average", {l[0], l[1], l[2]}},
          {"build_type", build.build_type},
#ifdef NDEBUG
          {"ndebug", true},
#else
          {"ndebug", false},
#endif
          {"compiler", build.compiler},
          {"date_utc", utc_now()}};
}

}  // namespace vascsim
