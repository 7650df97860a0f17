#pragma once
// How a simulation thread runs a device-driven model in real time next to the haptic thread (the realtime
// haptic session, the viewer):
//  - DeformationThreads: the deformation's OpenMP team leaves one core to the haptic thread. An OpenMP team
//    spinning on every core starves it (measured: 918 Hz and a 3.9 ms p99 jitter with a solve on both cores).
//    OpenMP's thread count belongs to the thread that sets it: make it on the thread that runs the model.
//  - RealtimeClock: the wall clock the model must never run ahead of.

#include "vascsim/core/stopwatch.hpp"

namespace vascsim {

/// Sets the calling thread's OpenMP thread count to one less than the cores (at least one); restores it.
class DeformationThreads {
 public:
  DeformationThreads();
  ~DeformationThreads();
  DeformationThreads(const DeformationThreads&) = delete;
  DeformationThreads& operator=(const DeformationThreads&) = delete;

 private:
  int saved_;
};

/// The wall clock a realtime model keeps to: seconds since construction, or since the moment sync() set it to
/// a simulated time (after a pause or single steps, so the model neither sleeps off nor races through the
/// difference). One thread uses it.
class RealtimeClock {
 public:
  RealtimeClock() = default;
  double seconds() const { return seconds_since(origin_); }
  /// From now on seconds() counts from `sim_time_s`.
  void sync(double sim_time_s);
  /// Sleeps while `sim_time_s` is ahead of seconds(): the model never runs ahead of the wall clock.
  void wait_for(double sim_time_s) const;

 private:
  SteadyClock::time_point origin_ = SteadyClock::now();
};

}  // namespace vascsim
