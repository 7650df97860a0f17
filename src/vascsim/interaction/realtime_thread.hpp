#pragma once
// Asking the operating system to treat the calling thread as a real-time thread (the 1 kHz haptic loop):
// the SCHED_FIFO policy, so that it preempts the deformation and render threads the moment its deadline
// comes, and a 1 us timer slack, so that sleep_until wakes it within microseconds instead of Linux's default
// 50 us. Whether the system allows it depends on privileges (CAP_SYS_NICE or an RLIMIT_RTPRIO); a refusal
// is not an error, only reported.

#include <string>

namespace vascsim {

struct RealtimeSchedulingResult {
  bool fifo = false;         ///< SCHED_FIFO was granted
  int priority = 0;          ///< its priority, if granted
  int error = 0;             ///< errno of the refusal, if refused
  bool timer_slack = false;  ///< the 1 us timer slack was set
  /// e.g. "SCHED_FIFO priority 80, timer slack 1 us" or "SCHED_OTHER (SCHED_FIFO refused: ...)".
  std::string describe() const;
};

/// Requests SCHED_FIFO at `priority` (1..99) and a 1 us timer slack for the calling thread.
RealtimeSchedulingResult request_realtime_scheduling(int priority);

}  // namespace vascsim
