#include "vascsim/run/realtime_pacing.hpp"

#include <omp.h>
#include <algorithm>
#include <thread>

namespace vascsim {

DeformationThreads::DeformationThreads() : saved_(omp_get_max_threads()) {
  omp_set_num_threads(std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1));
}

DeformationThreads::~DeformationThreads() {
  omp_set_num_threads(saved_);
}

void RealtimeClock::sync(double sim_time_s) {
  origin_ = SteadyClock::now() -
            std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(sim_time_s));
}

void RealtimeClock::wait_for(double sim_time_s) const {
  const double ahead = sim_time_s - seconds();
  if (ahead > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
}

}  // namespace vascsim
