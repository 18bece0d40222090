// Inline fp16 conversion for the hot paths (blending, clears). Same bits as oitref/core/fp16.h.
#pragma once

#include <cstdint>
#include <cstring>

#include "oitref/core/minifloat.h"
#if defined(OITREF_HAVE_F16C)
#include <immintrin.h>
#endif

namespace oitref::detail {

inline uint16_t encodeHalfInline(float value, Rounding rounding) {
#if defined(OITREF_HAVE_F16C)
  if (rounding == Rounding::TowardZero) return _cvtss_sh(value, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
  return _cvtss_sh(value, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
#else
  return static_cast<uint16_t>(encodeMinifloat(value, kHalfSpec, rounding));
#endif
}

// Four lanes of floats (the blend kernels' v4f) as four halves, encodeHalfInline's rule in each:
// one VCVTPS2PH where built with F16C. The store of an RGBA16F texel by the blend kernels.
typedef float HalfLanes __attribute__((vector_size(16)));
inline void encodeHalf4Inline(HalfLanes value, Rounding rounding, uint16_t out[4]) {
#if defined(OITREF_HAVE_F16C)
  const __m128i packed = rounding == Rounding::TowardZero ? _mm_cvtps_ph((__m128)value, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)
                                                          : _mm_cvtps_ph((__m128)value, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(out), packed);
#else
  for (int c = 0; c < 4; ++c) out[c] = encodeHalfInline(value[c], rounding);
#endif
}

inline float decodeHalfInline(uint16_t bits) {
#if defined(OITREF_HAVE_F16C)
  return _cvtsh_ss(bits);
#else
  return decodeMinifloat(bits, kHalfSpec);
#endif
}

// Four halves packed in 64 bits (channel 0 lowest) as four lanes of floats, decodeHalfInline's
// rule in each: one VCVTPH2PS from a register (a texel of fewer channels, put together without a
// store-forwarding stall).
inline HalfLanes decodeHalf4Bits(uint64_t bits) {
#if defined(OITREF_HAVE_F16C)
  return (HalfLanes)_mm_cvtph_ps(_mm_cvtsi64_si128(int64_t(bits)));
#else
  return HalfLanes{decodeHalfInline(uint16_t(bits)), decodeHalfInline(uint16_t(bits >> 16)), decodeHalfInline(uint16_t(bits >> 32)),
                   decodeHalfInline(uint16_t(bits >> 48))};
#endif
}

// fp32 → fp16 → fp32 in four lanes: what a half target stores, read back (encodeHalfInline's
// rule, then the exact decode), without leaving the registers.
inline HalfLanes roundThroughHalf4(HalfLanes x, Rounding rounding) {
#if defined(OITREF_HAVE_F16C)
  const __m128i h = rounding == Rounding::TowardZero ? _mm_cvtps_ph((__m128)x, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)
                                                     : _mm_cvtps_ph((__m128)x, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  return (HalfLanes)_mm_cvtph_ps(h);
#else
  HalfLanes r;
  for (int c = 0; c < 4; ++c) r[c] = decodeHalfInline(encodeHalfInline(x[c], rounding));
  return r;
#endif
}

#if defined(OITREF_HAVE_F16C)
// Four consecutive halves (an RGBA16F texel) as four floats: one conversion for the four, the same
// per-element rule as decodeHalfInline (VCVTPH2PS, exact for every half).
inline __m128 decodeHalf4Vector(const uint8_t* texel) {
  return _mm_cvtph_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(texel)));  // 8 bytes, unaligned
}
#endif
// n consecutive halves into floats, one decodeHalfInline each (the portable build's row path).
inline void decodeHalvesInline(const uint8_t* halves, int n, float* out) {
  for (int i = 0; i < n; ++i) {
    uint16_t bits;
    std::memcpy(&bits, halves + 2 * i, 2);
    out[i] = decodeHalfInline(bits);
  }
}
inline void decodeHalf4Inline(const uint8_t* texel, float* out) {
#if defined(OITREF_HAVE_F16C)
  const __m128 f = decodeHalf4Vector(texel);
  std::memcpy(out, &f, 16);
#else
  decodeHalvesInline(texel, 4, out);
#endif
}

}  // namespace oitref::detail
