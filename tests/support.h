// Helpers shared by the tests: deterministic random bit patterns and float utilities.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace oitref::test {

inline float fromBits(uint32_t u) { return std::bit_cast<float>(u); }
inline uint32_t toBits(float f) { return std::bit_cast<uint32_t>(f); }

// Seeded stream of fp32 bit patterns (std::mt19937's sequence is fixed by the standard).
struct BitStream {
  std::mt19937 engine;
  explicit BitStream(uint32_t seed) : engine(seed) {}
  uint32_t next() { return engine(); }
  float nextFloat01() { return float(engine() >> 8) * (1.0f / 16777216.0f); }
  float uniform(float lo, float hi) { return lo + (hi - lo) * nextFloat01(); }
};

// Every float within `radius` ulps of v (both signs of direction), finite only.
inline std::vector<float> neighbourhood(float v, int radius) {
  std::vector<float> out;
  float lo = v, hi = v;
  out.push_back(v);
  for (int i = 0; i < radius; ++i) {
    lo = std::nextafter(lo, -INFINITY);
    hi = std::nextafter(hi, INFINITY);
    out.push_back(lo);
    out.push_back(hi);
  }
  return out;
}

}  // namespace oitref::test
