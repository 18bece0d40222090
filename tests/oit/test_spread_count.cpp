// SpreadCount: what many threads add is counted exactly, whatever their number.
#include <catch2/catch.hpp>

#include <cstdint>
#include <thread>
#include <vector>

#include "methods/spread_count.h"

using oitref::methods::SpreadCount;

namespace {

// `threads` threads, thread t adding t + 1 to the count `adds` times: Σ (t + 1)·adds in closed form.
uint64_t countFrom(SpreadCount& count, int threads, int adds) {
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t)
    workers.emplace_back([&count, t, adds] {
      for (int i = 0; i < adds; ++i) count.add(uint64_t(t) + 1);
    });
  for (std::thread& w : workers) w.join();
  return uint64_t(threads) * uint64_t(threads + 1) / 2 * uint64_t(adds);
}

}  // namespace

TEST_CASE("SpreadCount: adds from many threads sum exactly, also beyond its 64 slots", "[spread_count]") {
  for (const int threads : {1, 2, 7, 100}) {
    SpreadCount count;
    const uint64_t expected = countFrom(count, threads, 20000);
    INFO(threads << " threads");
    CHECK(count.total() == expected);
  }
  SpreadCount fresh;
  CHECK(fresh.total() == 0);
}
