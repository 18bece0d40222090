// Seeded uniform numbers that are the same on every platform: std::mt19937's sequence is fixed
// by the C++ standard, its distributions are not, so the mapping to [0, 1) is done here — the
// top 24 bits of each output times 2^-24, exact in float and double alike.
#pragma once

#include <cstdint>
#include <random>

namespace oitref::util {

// SplitMix64 (Steele, Lea, Flood 2014): advances `state` and returns a well-mixed 64-bit hash of
// it, for random numbers that are a function of a key (a pixel, a fragment) rather than a sequence.
inline uint64_t splitMix64(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

class SeededRandom {
 public:
  explicit SeededRandom(uint32_t seed) : engine_(seed) {}
  double unit() { return double(engine_() >> 8) * (1.0 / 16777216.0); }  // in [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  float uniformFloat(float lo, float hi) { return lo + (hi - lo) * float(unit()); }
  uint32_t bits() { return uint32_t(engine_()); }                  // 32 uniform bits
  uint32_t below(uint32_t n) { return uint32_t(unit() * double(n)); }  // in [0, n), n ≤ 2^24

 private:
  std::mt19937 engine_;
};

}  // namespace oitref::util
