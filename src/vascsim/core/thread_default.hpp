#pragma once
// How many OpenMP threads vascsim uses when the user chooses none (no -j, no OMP_NUM_THREADS): the cores that
// other work leaves idle. On a loaded machine every parallel region waits for its slowest thread, and a
// thread that shares its core with another process waits for a time slice: beside other work, two threads
// were measured up to 10x slower per force evaluation than on an idle machine while one thread slowed by at
// most 1.6x (docs/performance.md, section 6); OMP_WAIT_POLICY=passive did not change that.

namespace vascsim {

/// max(1, cores - busy), at most `cores`, with busy = round(load_average) (0 when the load is unknown, i.e.
/// negative). The 1-minute load average still counts work that ended seconds ago (a previous run of a
/// script), so when `others_running` (the other processes runnable right now; negative: unknown) is known,
/// busy is at most that: both must say the cores are taken.
int default_thread_count(int cores, double load_average, int others_running = -1);

}  // namespace vascsim
