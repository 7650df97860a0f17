#include "vascsim/core/thread_default.hpp"

#include <algorithm>
#include <cmath>

namespace vascsim {

int default_thread_count(int cores, double load_average, int others_running) {
  cores = std::max(cores, 1);
  if (!(load_average >= 0.0)) return cores;
  int busy = static_cast<int>(std::lround(std::min(load_average, static_cast<double>(cores))));
  if (others_running >= 0) busy = std::min(busy, others_running);
  return std::clamp(cores - busy, 1, cores);
}

}  // namespace vascsim
