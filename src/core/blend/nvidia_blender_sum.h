// The NVIDIA float blender's sum of its two exact products (blend_nvidia.h, "Float targets"),
// written once for one channel (double with int64_t: blendNvidia's rules) and for four channels
// in vector lanes (lanes::d4 with lanes::i4: the planned kernel's usual fragments), with the same
// IEEE and integer operations in every lane. The lanes hold their integers in 32 bits (every
// integer here is below 2^31 in magnitude), which AVX converts to and from doubles natively.
#pragma once

#include <bit>
#include <cstdint>
#include <type_traits>

#include "oitref/core/lanes.h"

namespace oitref::detail::nvidia_sum {

// The integer type that goes with a double type.
template <typename D>
using IntOf = std::conditional_t<lanes::isVector<D>, lanes::i4, int64_t>;

// The 32-bit halves of four doubles, as floats: AVX shuffles float lanes in one instruction where
// it would take several for integer lanes.
typedef float F32x8 __attribute__((vector_size(32)));

// The upper 32 bits of each double (sign, exponent, top of the significand), or of each lane of a
// comparison's result.
template <typename D>
inline IntOf<D> upperBits(D x) {
  if constexpr (lanes::isVector<D>) {
    const F32x8 words = (F32x8)x;  // a vector cast keeps the bits
    return (lanes::i4)__builtin_shufflevector(words, words, 1, 3, 5, 7);
  } else {
    return std::bit_cast<int64_t>(x) >> 32;
  }
}
template <typename D, typename M>
inline IntOf<D> maskOf(M comparison) {  // a comparison of doubles as an IntOf<D> mask
  if constexpr (lanes::isVector<D>) return upperBits<D>((D)comparison);
  else return -IntOf<D>(comparison);
}
// 2^k, k in [−1022, 1023].
template <typename D>
inline D powerOfTwo(IntOf<D> k) {
  if constexpr (lanes::isVector<D>) {
    const lanes::f4 upper = (lanes::f4)((k + 1023) << 20), zero{};
    return (D)__builtin_shufflevector(zero, upper, 0, 4, 1, 5, 2, 6, 3, 7);
  } else {
    return std::bit_cast<double>((k + 1023) << 52);
  }
}
template <typename I>
inline I select(I mask, I a, I b) {  // mask: all ones or zero per lane
  return (a & mask) | (b & ~mask);
}
template <typename I, typename C>
inline I maskFrom(C comparison) {  // a comparison of integers as a mask
  if constexpr (lanes::isVector<I>) return comparison;
  else return -I(comparison);
}

// x·2^−L rounded to an integer with the sticky bit: toward zero, then its last bit set if
// inexact. |x·2^−L| < 2^(p+4) ≤ 2^28 (x a product below 2^e, L = e − p − 4): exact, and it fits.
template <typename D>
inline IntOf<D> roundToOdd(D x, IntOf<D> L) {
  using I = IntOf<D>;
  const D scaled = x * powerOfTwo<D>(-L);
  const I t = lanes::convert<I>(scaled);  // toward zero
  const I inexact = maskOf<D>(lanes::convert<D>(t) != scaled);
  const I magnitude = select<I>(maskFrom<I>(t < 0), -t, t) | (inexact & 1);
  return select<I>(maskFrom<I>(upperBits<D>(x) < 0), -magnitude, magnitude);  // x's sign (also of −0)
}

// s·Sf ± d·Df from its exact products pa, pb (0 for a term that is zero or left out) and e, the
// larger of the two terms' exponent estimates exp(value) + exp(factor) (frexp exponents; the
// product lies in [2^(e−2), 2^e)). Each product is rounded to odd at 2^L, L = e − p − 4; the sum T
// of the two is exact; if T's last place (p bits below its leading bit, or the denormal grid
// 2^minExponent) falls below 2^(L+2), its last bit (the sticky) is dropped, else it is left for
// the caller's rounding to nearest even. An exact cancellation is +0.
template <typename D>
inline D blenderSum(D pa, D pb, IntOf<D> e, int p, int minExponent) {
  using I = IntOf<D>;
  I L = e - (p + 4);
  I sum = roundToOdd<D>(pa, L) + roundToOdd<D>(pb, L);
  // bit_width(|T|) from the exponent of |T| as a double (exact: |T| < 2^31); T = 0 reads as 1.
  const I magnitude = select<I>(maskFrom<I>(sum < 0), -sum, sum) | (maskFrom<I>(sum == 0) & 1);
  const I width = ((upperBits<D>(lanes::convert<D>(magnitude)) >> 20) & 0x7ff) - 1022;
  // max(L + width − p, minExponent) < L + 2, both sides checked.
  const I drop = maskFrom<I>(width - p < 2) & maskFrom<I>(L + 2 > minExponent) & 1;
  sum = select<I>(-drop, (sum - maskFrom<I>(sum < 0)) >> 1, sum);  // halved toward zero
  L += drop;
  return lanes::convert<D>(sum) * powerOfTwo<D>(L);  // exact: |T| < 2^(p+6), L > −400
}

}  // namespace oitref::detail::nvidia_sum
