#include "vascsim/experiments/machine_info.hpp"

#include "vascsim/core/build_info.hpp"

#include <omp.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
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

namespace {

// procs_running of /proc/stat (this process included); -1 when unreadable.
long procs_running() {
  std::ifstream stat("/proc/stat");
  std::string key;
  long value = 0;
  while (stat >> key) {
    if (key == "procs_running" && stat >> value) return value;
    stat.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return -1;
}

// This process's threads that are runnable now (state R in /proc/self/task/*/stat): at start-up OpenBLAS's
// workers spin for a while, and they must not count as other work.
long own_running_threads() {
  long running = 0;
  std::error_code ec;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
    std::ifstream stat(task.path() / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    const std::size_t close = line.rfind(')');  // the name in parentheses may hold spaces
    if (close != std::string::npos && close + 2 < line.size() && line[close + 2] == 'R') ++running;
  }
  return running;
}

}  // namespace

int other_runnable_processes() {
  // The fewest of three samples 5 ms apart: a process that keeps a core busy is runnable in every one, a
  // short-lived one (a shell, a kernel worker) rarely in all three.
  long fewest = -1;
  for (int k = 0; k < 3; ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const long all = procs_running();
    if (all < 0) return -1;
    const long others = std::max(all - std::max(own_running_threads(), 1L), 0L);
    fewest = fewest < 0 ? others : std::min(fewest, others);
    if (fewest == 0) break;
  }
  return static_cast<int>(fewest);
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
