#pragma once
// Progress on long runs: a redrawn bar on a terminal, plain lines otherwise (logs, CI), nothing with -q.

#include <chrono>
#include <ostream>
#include <string>

namespace vascsim {

class Progress {
 public:
  /// `quiet` (the -q flag: only warnings and errors): it prints nothing.
  Progress(std::ostream& out, bool terminal, std::string label, bool quiet = false);
  /// Reports `done` of `total` with a short status text (shown as at most `total`: a session that runs past
  /// its nominal end is at 100 %).
  void update(int done, int total, const std::string& status);
  void finish();

 private:
  std::ostream& out_;
  bool terminal_;
  bool quiet_;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  bool drawn_ = false;
};

}  // namespace vascsim
