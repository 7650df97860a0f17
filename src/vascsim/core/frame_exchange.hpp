#pragma once
// Hands the newest frame (the viewer's surface snapshot, render/render_frame.hpp) from the simulation thread
// to the render thread without either ever waiting for the other.
//
// Choice: interaction/latest_value.hpp is a lock-free triple buffer, but it copies the value in write()
// and so needs a trivially copyable type. A frame holds vectors. This is the same triple buffer
// (three slots, a shared "middle" index with a fresh bit, one atomic exchange per hand-off) with the
// copy left to the caller: the producer fills the slot it owns in place (back(), which keeps its vectors'
// capacity, so a steady stream of same-sized frames allocates nothing), then publish() swaps it into the
// middle; the consumer's update() swaps the middle out if it is fresh. No mutex: the render thread never
// blocks the simulation or the haptic loop, and a slow reader skips frames.
//
// Memory ordering as in LatestValue: both exchanges are acq_rel on the same atomic, so the producer's
// writes to a slot happen before the consumer's reads of it, and the consumer's reads of the slot it
// hands back happen before the producer writes it again.

#include <array>
#include <atomic>
#include <cstdint>

namespace vascsim {

template <typename T>
class FrameExchange {
 public:
  FrameExchange() = default;
  FrameExchange(const FrameExchange&) = delete;
  FrameExchange& operator=(const FrameExchange&) = delete;

  /// Producer only. The slot to fill. It holds an older frame (or a default T): overwrite all of it.
  T& back() { return slots_[back_].value; }

  /// Producer only. Makes back() the newest frame; a frame the consumer has not taken yet is dropped.
  void publish() {
    const std::uint8_t previous =
        middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = previous & kIndexMask;
  }

  /// Producer only. The last published frame has not been taken yet: a frame published now would replace
  /// it unseen, so a producer may skip preparing one (a relaxed hint: a take may be seen late).
  bool pending() const { return (middle_.load(std::memory_order_relaxed) & kFresh) != 0; }

  /// Consumer only. Takes the newest published frame if there is one (true). Never blocks.
  bool update() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = previous & kIndexMask;
    return true;
  }

  /// Consumer only. The frame taken by the last update() (a default T before the first); unchanged until
  /// the next update().
  const T& front() const { return slots_[front_].value; }

 private:
  static constexpr std::uint8_t kIndexMask = 0x3;
  static constexpr std::uint8_t kFresh = 0x4;
  struct alignas(64) Slot {
    T value{};
  };
  std::array<Slot, 3> slots_{};
  alignas(64) std::atomic<std::uint8_t> middle_{1};
  alignas(64) std::uint8_t back_ = 0;
  alignas(64) std::uint8_t front_ = 2;
};

}  // namespace vascsim
