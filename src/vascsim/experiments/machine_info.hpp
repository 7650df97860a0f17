#pragma once
// What a timing was measured on: the CPU model, the cores, the load average (other processes on the cores
// distort every wall-clock number, docs/performance.md section 6), the build and the date. Recorded beside
// every timing the experiments write (`vascsim bench`, `vascsim experiment timing`).

#include <nlohmann/json.hpp>
#include <string>

namespace vascsim {

/// The 1-minute load average (-1 if unknown).
double load_average_1min();

/// The threads of other processes runnable right now (/proc/stat procs_running less this process's running
/// threads, the fewest of three samples over 10 ms); -1 when unknown.
int other_runnable_processes();

/// Now, as 2026-01-31T12:00:00Z.
std::string utc_now();

/// {"cpu_model", "hardware_concurrency", "omp_num_procs", "omp_max_threads", "load_average" [1, 5, 15 min],
///  "build_type", "ndebug", "compiler", "date_utc"}.
nlohmann::json machine_info();

}  // namespace vascsim
