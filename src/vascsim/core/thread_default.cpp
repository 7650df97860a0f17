#include "vascsim/core/thread_default.hpp"

#include <algorithm>
#include <cmath>

namespace vascsim {

int default_thread_count(int cores, double load_average) {
  cores = std::max(cores, 1);
  if (!(load_average >= 0.0)) return cores;
  const int busy = static_cast<int>(std::lround(load_average));
  return std::clamp(cores - busy, 1, cores);
}

}  // namespace vascsim
