// The triple buffer that hands whole frames (vectors: not trivially copyable) from the simulation thread to
// the render thread (core/frame_exchange.hpp): the reader sees complete frames in order, never a torn one,
// and the last frame arrives. Runs under ThreadSanitizer (make test-threads).

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "vascsim/core/frame_exchange.hpp"

namespace vascsim {
namespace {

struct SequencedFrame {
  std::uint64_t sequence = 0;
  std::vector<float> values;
};

TEST(FrameExchange, TheReaderSeesWholeFramesInOrderWhileTheWriterNeverWaits) {
  FrameExchange<SequencedFrame> exchange;
  constexpr int kFrames = 20000;
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (int i = 1; i <= kFrames; ++i) {
      SequencedFrame& f = exchange.back();
      f.sequence = static_cast<std::uint64_t>(i);
      f.values.assign(64 + i % 7, static_cast<float>(i));
      exchange.publish();
    }
    done = true;
  });
  std::uint64_t last = 0;
  int seen = 0;
  for (;;) {
    const bool finished = done.load();  // read first: a publish before it is seen by the update below
    if (!exchange.update()) {
      if (finished) break;
      continue;
    }
    const SequencedFrame& f = exchange.front();
    ASSERT_GT(f.sequence, last);
    last = f.sequence;
    ++seen;
    ASSERT_EQ(f.values.size(), 64u + f.sequence % 7);
    for (const float v : f.values) ASSERT_EQ(v, static_cast<float>(f.sequence));  // not torn
  }
  producer.join();
  EXPECT_EQ(exchange.front().sequence, static_cast<std::uint64_t>(kFrames));  // the last frame arrives
  EXPECT_GT(seen, 0);
}

TEST(FrameExchange, FrontIsADefaultFrameUntilTheFirstPublish) {
  FrameExchange<SequencedFrame> exchange;
  EXPECT_FALSE(exchange.update());
  EXPECT_FALSE(exchange.pending());
  EXPECT_EQ(exchange.front().sequence, 0u);
  exchange.back().sequence = 7;
  exchange.publish();
  EXPECT_TRUE(exchange.pending());  // published, not taken yet
  EXPECT_TRUE(exchange.update());
  EXPECT_FALSE(exchange.pending());
  EXPECT_EQ(exchange.front().sequence, 7u);
  EXPECT_FALSE(exchange.update());
}

}  // namespace
}  // namespace vascsim
