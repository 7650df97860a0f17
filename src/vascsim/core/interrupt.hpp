#pragma once
// Ctrl-C (SIGINT) and SIGTERM during a run: the handler only raises a flag; the drivers look at it at every
// step boundary, stop there, and finish what they write (summary.json says "interrupted", the .pvd index
// lists the frames written), and the CLI exits with kInterruptedExitCode. A second signal ends the process at
// once.

namespace vascsim {

/// 128 + SIGINT, as shells report a process ended by Ctrl-C.
inline constexpr int kInterruptedExitCode = 130;

/// Installs the handler for SIGINT and SIGTERM (idempotent); the previous handlers come back with the guard's
/// end.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
};

/// True once a signal arrived (or request_interrupt was called).
bool interrupt_requested();
/// What the handler does; also for tests.
void request_interrupt();
/// Lowers the flag (a new run, a test).
void clear_interrupt();

}  // namespace vascsim
