// The default OpenMP thread count: the cores the load average leaves idle, at least one.

#include <gtest/gtest.h>

#include "vascsim/core/thread_default.hpp"

namespace vascsim {
namespace {

TEST(ThreadDefault, CoresTheLoadLeavesIdle) {
  EXPECT_EQ(default_thread_count(2, 0.1), 2);   // idle machine: every core
  EXPECT_EQ(default_thread_count(2, 0.7), 1);   // another process holds most of a core
  EXPECT_EQ(default_thread_count(2, 11.9), 1);  // heavily loaded: one thread, never zero
  EXPECT_EQ(default_thread_count(8, 2.4), 6);
  EXPECT_EQ(default_thread_count(4, -1.0), 4);  // load unknown: every core
  EXPECT_EQ(default_thread_count(0, 0.0), 1);
}

// The load average remembers a run that just ended; the processes runnable now do not. Both must say busy.
TEST(ThreadDefault, LoadFromWorkThatHasEndedDoesNotCount) {
  EXPECT_EQ(default_thread_count(2, 1.0, 0), 2);   // a script's previous run: nothing else runs now
  EXPECT_EQ(default_thread_count(2, 1.0, 1), 1);   // another process runs now and has for a minute
  EXPECT_EQ(default_thread_count(2, 0.1, 3), 2);   // a momentary burst alone does not count
  EXPECT_EQ(default_thread_count(2, 1.0, -1), 1);  // runnable count unknown: the load average alone
  EXPECT_EQ(default_thread_count(4, 9.0, 9), 1);
}

}  // namespace
}  // namespace vascsim
