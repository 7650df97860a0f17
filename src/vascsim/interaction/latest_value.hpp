#pragma once
// A lock-free hand-off of the latest value from one producer thread to one consumer thread (a triple
// buffer). The haptic thread and the simulation thread use one in each direction (docs/haptics.md):
// neither ever waits for the other, and a slow side simply skips the values it was too slow to see.
//
// Three slots: the producer owns one ("back"), the consumer owns one ("front"), and the third
// ("middle") is in the shared atomic `middle_` together with a "fresh" bit. write() fills the back slot
// and swaps it into the middle; update() swaps the middle slot out if it is fresh. Each side only
// ever touches the slot it owns, so a value is copied while nobody else can see that slot, and a
// reader can never see a half-written (torn) value.
//
// Memory ordering: both swaps are exchange(acq_rel) on the same atomic.
//  - write(): release publishes the slot's contents to the consumer that later acquires it; acquire
//    makes the consumer's last reads of the slot it hands back happen before the producer overwrites it.
//  - update(): acquire sees the producer's copy into the slot it takes; release hands back the old
//    front slot only after the consumer has finished reading it.
// The relaxed pre-check in update() is only a hint to skip the exchange when nothing is new: if it
// sees a stale "not fresh", the value shows up at the next call.

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace vascsim {

template <typename T>
class LatestValue {
  // Trivially copyable: a copy is a plain memcpy that cannot throw, lock or allocate.
  static_assert(std::is_trivially_copyable_v<T>, "LatestValue<T> needs a trivially copyable T");

 public:
  /// Every slot starts as `initial`, so the consumer reads `initial` until the first write().
  explicit LatestValue(const T& initial = T{}) {
    for (Slot& s : slots_) s.value = initial;
  }
  LatestValue(const LatestValue&) = delete;
  LatestValue& operator=(const LatestValue&) = delete;

  /// Producer only. Publishes `value`; it replaces any value the consumer has not taken yet.
  /// Wait-free: one copy and one atomic exchange.
  void write(const T& value) {
    slots_[back_].value = value;
    const std::uint8_t previous =
        middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = previous & kIndexMask;
  }

  /// Consumer only. Takes the newest published value if there is one; returns true if it did. Never
  /// blocks. After it, value() is the newest complete value the producer has published.
  bool update() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = previous & kIndexMask;
    return true;
  }

  /// Consumer only. The value taken by the last update() (or `initial`). The reference stays valid
  /// and unchanged until the consumer's next update().
  const T& value() const { return slots_[front_].value; }

  /// Consumer only. update() then value().
  const T& read() {
    update();
    return value();
  }

 private:
  static constexpr std::uint8_t kIndexMask = 0x3;
  static constexpr std::uint8_t kFresh = 0x4;

  // One cache line per slot, and the atomic on its own line, so the two threads do not share lines
  // they both write.
  struct alignas(64) Slot {
    T value;
  };
  std::array<Slot, 3> slots_{};
  alignas(64) std::atomic<std::uint8_t> middle_{1};  // slot 1, not fresh
  alignas(64) std::uint8_t back_ = 0;                // producer's slot
  alignas(64) std::uint8_t front_ = 2;               // consumer's slot
};

}  // namespace vascsim
