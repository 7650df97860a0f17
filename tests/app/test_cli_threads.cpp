// `-j N` (app/cli.cpp): N in [1, 256]; anything else is one line naming the range and exit code 2, and a
// count that the process may not start (a limit on processes or memory) is one line and exit code 2 too,
// where OpenMP used to end the process ("libgomp: Thread creation failed", exit 1). In-process through
// run_cli.

#include <gtest/gtest.h>
#include <omp.h>
#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "support/cli_capture.hpp"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define VASCSIM_CLI_THREADS_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define VASCSIM_CLI_THREADS_SANITIZED 1
#endif
#endif

namespace vascsim {
namespace {

using test::CliCapture;
using test::run_cli_captured;

/// `vascsim -j <threads> check <a scene that does not exist>`, with OpenMP's thread count put back afterwards
/// (an accepted -j sets it for the whole test process). The missing scene tells a rejected -j (its own
/// message) from an accepted one (the scene's).
CliCapture run_with_threads(const std::string& threads) {
  const int previous = omp_get_max_threads();
  CliCapture r = run_cli_captured({"-j", threads, "check", "no-such-scene.json"});
  omp_set_num_threads(previous);
  return r;
}

// 1024 was the bound before: it reached OpenMP, which aborted where a process limit allowed fewer threads.
TEST(CliThreads, AboveTheBoundIsOneLineNamingTheRangeAndExitCode2) {
  for (const std::string threads : {"257", "1024", "100000"}) {
    SCOPED_TRACE(threads);
    const CliCapture r = run_with_threads(threads);
    EXPECT_EQ(r.code, 2) << r.err;
    ASSERT_EQ(r.messages.size(), 1u) << r.err;
    EXPECT_NE(r.messages[0].find("--threads: Value " + threads + " not in range 1 to 256"), std::string::npos)
        << r.messages[0];
    EXPECT_EQ(r.messages[0].find("no-such-scene"), std::string::npos) << r.messages[0];
  }
}

// The same bound for OMP_NUM_THREADS (its first count: OpenMP's is a list per nesting level) and for bench's
// --threads, which reached OpenMP unbounded.
TEST(CliThreads, OmpNumThreadsAndBenchThreadsHaveTheSameBound) {
  const char* before = std::getenv("OMP_NUM_THREADS");
  const std::string saved = before ? before : "";
  for (const std::string value : {"1024", "300,2"}) {
    SCOPED_TRACE(value);
    setenv("OMP_NUM_THREADS", value.c_str(), 1);
    const CliCapture r = run_cli_captured({"check", "no-such-scene.json"});
    EXPECT_EQ(r.code, 2) << r.err;
    ASSERT_EQ(r.messages.size(), 1u) << r.err;
    EXPECT_NE(r.messages[0].find("OMP_NUM_THREADS=" + value + ": at most 256 threads"), std::string::npos)
        << r.messages[0];
  }
  setenv("OMP_NUM_THREADS", "2", 1);
  const CliCapture ok = run_cli_captured({"check", "no-such-scene.json"});
  EXPECT_NE(ok.err.find("no-such-scene"), std::string::npos) << ok.err;  // accepted: the scene's own error
  if (before)
    setenv("OMP_NUM_THREADS", saved.c_str(), 1);
  else
    unsetenv("OMP_NUM_THREADS");
  const CliCapture bench = run_cli_captured({"bench", "--threads", "1,1024"});
  EXPECT_EQ(bench.code, 2) << bench.err;
  ASSERT_EQ(bench.messages.size(), 1u) << bench.err;
  EXPECT_NE(bench.messages[0].find("1024 not in range 1 to 256"), std::string::npos) << bench.messages[0];
}

TEST(CliThreads, ZeroOrNegativeIsOneLineNamingTheRangeAndExitCode2) {
  for (const std::string threads : {"0", "-1", "-1024"}) {
    SCOPED_TRACE(threads);
    const CliCapture r = run_with_threads(threads);
    EXPECT_EQ(r.code, 2) << r.err;
    ASSERT_EQ(r.messages.size(), 1u) << r.err;
    EXPECT_NE(r.messages[0].find("not in range 1 to 256"), std::string::npos) << r.messages[0];
  }
}

// The bound itself is accepted: 256 threads are started and ended, then the command runs (and fails on the
// missing scene, the only message).
TEST(CliThreads, TheBoundItselfIsAccepted) {
  const CliCapture r = run_with_threads("256");
  EXPECT_EQ(r.code, 2) << r.err;
  ASSERT_EQ(r.messages.size(), 1u) << r.err;
  EXPECT_NE(r.messages[0].find("no-such-scene.json"), std::string::npos) << r.messages[0];
}

TEST(CliThreads, TheHelpStatesTheRange) {
  const CliCapture r = run_cli_captured({"--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("OpenMP threads, 1 to 256"), std::string::npos) << r.out;
}

/// Lowers this process's address-space limit for its lifetime (the soft limit only: it can be raised back).
class AddressSpaceLimit {
 public:
  explicit AddressSpaceLimit(rlim_t bytes) {
    getrlimit(RLIMIT_AS, &previous_);
    rlimit lowered = previous_;
    lowered.rlim_cur = bytes;
    set_ = setrlimit(RLIMIT_AS, &lowered) == 0;
  }
  ~AddressSpaceLimit() { setrlimit(RLIMIT_AS, &previous_); }
  AddressSpaceLimit(const AddressSpaceLimit&) = delete;
  AddressSpaceLimit& operator=(const AddressSpaceLimit&) = delete;
  bool set() const { return set_; }

 private:
  rlimit previous_{};
  bool set_ = false;
};

// Threads that cannot be started: -j 256 with room for the stacks of about 8 more threads. A process limit
// (ulimit -u) does not bind root, who runs the tests in the container; an address-space limit makes
// pthread_create fail in the same way (EAGAIN) for any user. Before the check, -j 256 was set and the first
// parallel region ended the process in OpenMP's runtime (exit 1); here the command's own message came
// instead.
TEST(CliThreads, ThreadsThatCannotStartAreOneLineAndExitCode2) {
#ifdef VASCSIM_CLI_THREADS_SANITIZED
  GTEST_SKIP() << "the sanitizers reserve and map memory of their own under an address-space limit";
#else
  pthread_attr_t attr;
  std::size_t stack = 0;
  ASSERT_EQ(pthread_getattr_default_np(&attr), 0);
  pthread_attr_getstacksize(&attr, &stack);
  pthread_attr_destroy(&attr);
  const std::size_t headroom = 64u << 20;
  // 255 stacks must need far more than the headroom, whatever RLIMIT_STACK made the default stack size.
  if (255 * stack < 4 * headroom) GTEST_SKIP() << "default thread stacks of " << stack << " bytes";
  std::size_t pages = 0;
  std::ifstream("/proc/self/statm") >> pages;
  ASSERT_GT(pages, 0u);
  CliCapture r;
  {
    const AddressSpaceLimit limit(pages * static_cast<std::size_t>(sysconf(_SC_PAGESIZE)) + headroom);
    ASSERT_TRUE(limit.set());
    r = run_with_threads("256");
  }
  EXPECT_EQ(r.code, 2) << r.err;
  ASSERT_EQ(r.messages.size(), 1u) << r.err;
  EXPECT_EQ(r.messages[0].rfind("vascsim: error: -j 256: only ", 0), 0u) << r.messages[0];
  EXPECT_NE(r.messages[0].find("threads could be started"), std::string::npos) << r.messages[0];
  EXPECT_NE(r.messages[0].find("choose fewer threads"), std::string::npos) << r.messages[0];
#endif
}

}  // namespace
}  // namespace vascsim
