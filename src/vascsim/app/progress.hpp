#pragma once
// Progress on long runs: a redrawn bar on a terminal, plain lines otherwise (logs, CI).

#include <chrono>
#include <ostream>
#include <string>

namespace vascsim {

class Progress {
 public:
  Progress(std::ostream& out, bool terminal, std::string label);
  /// Reports `done` of `total` with a short status text.
  void update(int done, int total, const std::string& status);
  void finish();

 private:
  std::ostream& out_;
  bool terminal_;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  bool drawn_ = false;
};

}  // namespace vascsim
