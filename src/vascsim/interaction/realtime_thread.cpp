#include "vascsim/interaction/realtime_thread.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <fmt/format.h>
#include <cerrno>
#include <cstring>

namespace vascsim {

std::string RealtimeSchedulingResult::describe() const {
  const std::string slack = timer_slack ? ", timer slack 1 us" : "";
  if (fifo) return fmt::format("SCHED_FIFO priority {}{}", priority, slack);
  return fmt::format("SCHED_OTHER (SCHED_FIFO refused: {}){}", std::strerror(error), slack);
}

RealtimeSchedulingResult request_realtime_scheduling(int priority) {
  RealtimeSchedulingResult r;
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) {
    r.fifo = true;
    r.priority = priority;
  } else {
    r.error = rc;
  }
  r.timer_slack = prctl(PR_SET_TIMERSLACK, 1000UL, 0, 0, 0) == 0;  // nanoseconds
  return r;
}

}  // namespace vascsim
