#pragma once
// Wall-clock timing of set-up, steps and sessions (steady_clock: never jumps with the system time).

#include <chrono>

namespace vascsim {

using SteadyClock = std::chrono::steady_clock;

/// Seconds from `a` to `b`.
inline double seconds_between(SteadyClock::time_point a, SteadyClock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// Seconds since `start`.
inline double seconds_since(SteadyClock::time_point start) {
  return seconds_between(start, SteadyClock::now());
}

/// Measures the time since it was made (or last restarted).
class Stopwatch {
 public:
  Stopwatch() : start_(SteadyClock::now()) {}
  double seconds() const { return seconds_since(start_); }
  void restart() { start_ = SteadyClock::now(); }
  SteadyClock::time_point start() const { return start_; }

 private:
  SteadyClock::time_point start_;
};

}  // namespace vascsim
