// A count that a pass's workers add to at once, such as MBOIT's reconstructions that fell back.
//
// Why not one std::atomic: every worker's add then takes the same cache line from the other
// cores. On dense at 1080p MBOIT added to one atomic once per batch that had a fallback (millions
// a frame), and with two threads that moving line cost its accumulate pass about 300 ms of CPU
// time (docs/speed.md, twenty-second round). Here each thread adds to a slot of its own, on a line
// of its own; the total is a sum of integers, the same for any order and thread count.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace oitref::methods {

class SpreadCount {
 public:
  void add(uint64_t n) { slots_[slotOfThisThread()].value.fetch_add(n, std::memory_order_relaxed); }
  uint64_t total() const {
    uint64_t sum = 0;
    for (const Slot& s : slots_) sum += s.value.load(std::memory_order_relaxed);
    return sum;
  }

 private:
  static constexpr size_t kSlots = 64;  // threads beyond 64 share slots: still right, only slower
  struct alignas(64) Slot {
    std::atomic<uint64_t> value{0};
  };
  // Each thread's slot, numbered in the order threads first count (the same for every SpreadCount).
  static size_t slotOfThisThread() {
    static std::atomic<size_t> threads{0};
    thread_local const size_t slot = threads.fetch_add(1, std::memory_order_relaxed) % kSlots;
    return slot;
  }
  std::array<Slot, kSlots> slots_;
};

}  // namespace oitref::methods
