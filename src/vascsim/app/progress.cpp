#include "vascsim/app/progress.hpp"

#include <fmt/format.h>
#include <algorithm>

namespace vascsim {

Progress::Progress(std::ostream& out, bool terminal, std::string label, bool quiet)
    : out_(out),
      terminal_(terminal),
      quiet_(quiet),
      label_(std::move(label)),
      start_(std::chrono::steady_clock::now()) {}

void Progress::update(int done, int total, const std::string& status) {
  if (quiet_) return;
  if (total > 0) done = std::min(done, total);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = total > 0 ? static_cast<double>(done) / total : 1.0;
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth + 0.5);
    out_ << fmt::format("\r{} [{}{}] {}/{} {:5.1f}s {}\033[K", label_, std::string(filled, '#'),
                        std::string(kWidth - filled, '.'), done, total, elapsed, status)
         << std::flush;
    drawn_ = true;
  } else {
    out_ << fmt::format("{}: {}/{} ({:.0f}%) {:.1f}s {}\n", label_, done, total, 100.0 * frac, elapsed,
                        status)
         << std::flush;
  }
}

void Progress::finish() {
  if (terminal_ && drawn_) out_ << "\n" << std::flush;
  drawn_ = false;
}

}  // namespace vascsim
