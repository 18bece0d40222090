// Unsigned normalized fixed point (UNORM): r8/rg8/rgba8, rgb10a2, d16/d24.
//
// GL 4.6 §2.3.5.2 (conversion from floating point to normalized fixed point): the value is
// clamped to [0,1] and f·(2^b − 1) is converted to one of the two nearest integers; GL prefers
// the nearest. Our modes:
//  * UnormRounding::ExactNearestEven (default): NaN -> 0, clamp to [0,1], then the *exact*
//    product f·(2^b−1) (computed in double, where it is exact for b ≤ 29) rounded to nearest,
//    ties to even.
//  * UnormRounding::Fp32Product: clamp, then the product rounded to fp32 first, then to the nearest
//    integer, ties to even — what `lrintf(f * 255.0f)` does and what Mesa's llvmpipe does. It
//    differs from the exact result for 128 inputs in [0,1] at b = 8 (the test lists them).
//  * UnormRounding::NvidiaFixed: what an NVIDIA Hopper GPU stores (docs/rules.md, "Profile
//    nvidia"): clamp (NaN -> 0), truncate to b + 4 fraction bits, X = floor(f·2^(b+4)), then
//    (X·(2^b − 1) + 2^(b+3) − 1) >> (b + 4): the product rounded to nearest, ties down.
// Decoding (GL 4.6 §2.3.5.1): k / (2^b − 1), correctly rounded to fp32.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "oitref/core/lanes.h"

namespace oitref {

enum class UnormRounding : uint8_t { ExactNearestEven, Fp32Product, NvidiaFixed };

// Clamp to [0,1] with NaN -> 0: the clamp GL applies to fixed-point blending inputs and outputs.
inline float clampUnit(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; }

// Round a non-negative double below 2^32 (below 2^31 for Int = int32_t) to the nearest integer,
// ties to even, whatever the floating-point environment's rounding mode (truncation and the exact
// difference do not depend on it). Also over four lanes (D = lanes::d4, Int = lanes::i4): the
// span kernels' depth encoding.
template <typename Int = uint32_t, typename D = double>
inline Int roundHalfEven(D p) {
  const Int q = lanes::convert<Int>(p);
  const D frac = p - lanes::convert<D>(q);  // exact
  // Without branches: the fraction is random in a depth or colour stream, so a branch on it
  // mispredicts half the time.
  const Int up = lanes::convert<Int>(frac > lanes::splat<D>(0.5)) | (lanes::convert<Int>(frac == lanes::splat<D>(0.5)) & q);
  return q + (up & 1);
}

inline uint32_t encodeUnorm(float value, int bits, UnormRounding rounding = UnormRounding::ExactNearestEven) {
  const uint32_t maxCode = (uint32_t(1) << bits) - 1;
  const float v = clampUnit(value);
  if (rounding == UnormRounding::NvidiaFixed) {
    const int fraction = bits + 4;  // f < 2^24 needs no more: the double product below is exact
    const uint64_t x = uint64_t(double(v) * double(uint64_t(1) << fraction));
    return uint32_t((x * maxCode + (uint64_t(1) << (fraction - 1)) - 1) >> fraction);
  }
  if (rounding == UnormRounding::Fp32Product) {
    const float product = v * float(maxCode);  // rounded to fp32 first
    return roundHalfEven(double(product));
  }
  // f has 24 significant bits, 2^b−1 at most b: the double product is exact for b ≤ 29.
  return roundHalfEven(double(v) * double(maxCode));
}

inline float decodeUnorm(uint32_t code, int bits) {
  return float(code) / float((uint32_t(1) << bits) - 1);  // one correctly rounded division
}
// llvmpipe's texture unit (its texel fetches and both of its filter paths) turns an 8-bit code
// into float with one fp32 multiply by fp32(1/255), not decodeUnorm's division: 126 of the 256
// codes come out an ulp away from it.
inline float decodeUnorm8Llvmpipe(uint32_t code) { return float(code) * (1.0f / 255.0f); }

// decodeUnorm(k, 8) of the four codes of an RGBA8 texel: where built with SSE4.1, the four
// divisions in one instruction (the same IEEE division, lane by lane), which costs less than four
// loads from a table of the 256 values and putting them together.
inline void decodeUnorm8x4(const uint8_t* texel, float out[4]) {
#if defined(__SSE4_1__)
  int32_t word;
  std::memcpy(&word, texel, 4);
  const __m128 v = _mm_div_ps(_mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(word))), _mm_set1_ps(255.0f));
  _mm_storeu_ps(out, v);
#else
  for (int c = 0; c < 4; ++c) out[c] = decodeUnorm(texel[c], 8);
#endif
}

}  // namespace oitref
