// Independent oracles for the conversions, sharing no code with src/:
//  * oracleUnorm: exact f·(2^b−1) with 128-bit integers, no floating point.
//  * MinifloatOracle: enumerates every finite value of a format from its bit fields (ldexp), and
//    rounds by searching that sorted table — nearest with ties to the even code, or the largest
//    magnitude not above (toward zero).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "oitref/core/minifloat.h"
#include "support.h"

namespace oitref::test {

// Round-to-nearest-even of f·(2^b − 1) for f in [0,1], exactly: f = m·2^e with integers.
inline uint32_t oracleUnorm(float f, int b) {
  if (!(f > 0.0f)) return 0;
  if (f >= 1.0f) return (1u << b) - 1;
  const uint32_t u = oitref::test::toBits(f);
  const uint32_t exp = u >> 23;
  const unsigned __int128 m = exp ? ((u & 0x7fffff) | 0x800000) : (u & 0x7fffff);
  const int shift = exp ? 150 - int(exp) : 149;  // f = m / 2^shift, shift > 0 here
  if (shift > 64) return 0;  // num < 2^33 is below half a unit (and a shift ≥ 128 is undefined)
  const unsigned __int128 num = m * ((unsigned __int128)((1u << b) - 1));
  const unsigned __int128 q = num >> shift;
  const unsigned __int128 rem = num - (q << shift);
  const unsigned __int128 half = (unsigned __int128)1 << (shift - 1);
  const bool up = rem > half || (rem == half && (q & 1));
  return uint32_t(q + (up ? 1 : 0));
}

struct MinifloatOracle {
  MinifloatSpec spec;
  std::vector<std::pair<double, uint32_t>> positive;  // finite non-negative values, ascending
  double maxFinite = 0;

  explicit MinifloatOracle(const MinifloatSpec& s) : spec(s) {
    const int E = s.exponentBits, M = s.mantissaBits, bias = (1 << (E - 1)) - 1;
    for (uint32_t e = 0; e < (1u << E); ++e)
      for (uint32_t m = 0; m < (1u << M); ++m) {
        const bool allOnes = e == (1u << E) - 1;
        if (s.specials == FloatSpecials::Ieee && allOnes) continue;
        if (s.specials == FloatSpecials::FiniteNan && allOnes && m == (1u << M) - 1) continue;
        // Denormals stay in the table even with flush-to-zero: the contract rounds first, then
        // flushes a denormal result (flushCode below).
        double v = e == 0 ? std::ldexp(double(m), 1 - bias - M) : std::ldexp(double(m + (1u << M)), int(e) - bias - M);
        positive.emplace_back(v, (e << M) | m);
      }
    std::sort(positive.begin(), positive.end());
    maxFinite = positive.back().first;
  }

  uint32_t sign() const { return s() ? 1u << (spec.exponentBits + spec.mantissaBits) : 0; }
  bool s() const { return spec.isSigned; }
  uint32_t infBits() const { return ((1u << spec.exponentBits) - 1) << spec.mantissaBits; }

  uint32_t flushCode(uint32_t code) const {
    return (!spec.denormals && (code >> spec.mantissaBits) == 0) ? 0 : code;
  }
  bool isDenormalCode(uint32_t code) const { return code != 0 && (code >> spec.mantissaBits) == 0; }

  // Finite, non-NaN input only.
  uint32_t encode(float f, Rounding r) const {
    const double x = double(f);
    const bool neg = std::signbit(f);
    if (!spec.isSigned && neg) return 0;
    const double a = std::fabs(x);
    const uint32_t sgn = neg ? sign() : 0;
    auto it = std::upper_bound(positive.begin(), positive.end(), std::make_pair(a, ~0u));
    // it: first value > a; prev: largest value <= a.
    const auto& below = *(it - 1);
    if (r == Rounding::TowardZero || it == positive.end()) {
      if (it == positive.end() && r == Rounding::NearestEven && a > below.first) {
        // Above the largest finite value: the IEEE overflow threshold is max + ulp/2.
        const double ulp = below.first - (it - 2)->first;
        const bool overflow = a > below.first + ulp / 2 || (a == below.first + ulp / 2 && (below.second & 1));
        if (overflow && spec.specials == FloatSpecials::Ieee && !spec.finiteOverflowSaturates)
          return sgn | infBits();
      }
      return sgn | flushCode(below.second);
    }
    const auto& above = *it;
    const double dBelow = a - below.first, dAbove = above.first - a;
    uint32_t code;
    if (dBelow < dAbove) code = below.second;
    else if (dAbove < dBelow) code = above.second;
    else code = (below.second & 1) ? above.second : below.second;
    return sgn | flushCode(code);
  }
};


}  // namespace oitref::test
