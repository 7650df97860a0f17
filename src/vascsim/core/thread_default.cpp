#include "vascsim/core/thread_default.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

namespace vascsim {

int default_thread_count(int cores, double load_average) {
  cores = std::max(cores, 1);
  if (!(load_average >= 0.0)) return cores;
  const int busy = static_cast<int>(std::lround(load_average));
  return std::clamp(cores - busy, 1, cores);
}

double load_average_1min() {
  std::ifstream in("/proc/loadavg");
  double load = -1.0;
  if (!(in >> load)) return -1.0;
  return load;
}

}  // namespace vascsim
