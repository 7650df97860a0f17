#include "vascsim/core/interrupt.hpp"

#include <atomic>
#include <csignal>

namespace vascsim {

namespace {

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the flag is set from a signal handler");

using Handler = void (*)(int);
Handler g_previous_int = SIG_DFL, g_previous_term = SIG_DFL;

extern "C" void on_signal(int signal) {
  g_interrupted.store(true);
  std::signal(signal, SIG_DFL);  // a second Ctrl-C ends the process
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_previous_int = std::signal(SIGINT, on_signal);
  g_previous_term = std::signal(SIGTERM, on_signal);
}

InterruptGuard::~InterruptGuard() {
  std::signal(SIGINT, g_previous_int == SIG_ERR ? SIG_DFL : g_previous_int);
  std::signal(SIGTERM, g_previous_term == SIG_ERR ? SIG_DFL : g_previous_term);
}

bool interrupt_requested() {
  return g_interrupted.load();
}
void request_interrupt() {
  g_interrupted.store(true);
}
void clear_interrupt() {
  g_interrupted.store(false);
}

}  // namespace vascsim
