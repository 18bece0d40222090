// The GL 4.6 §17.3.6 blend arithmetic on decoded fp32 values, used by every path that blends in
// floating point (the generic path and the per-format fast paths of target_blender.cpp), so the
// rule exists once. Rules: include/oitref/core/blend.h.
//
// A BlendState is compiled once per draw into per-lane selectors, so the per-fragment work has no
// branches and runs four lanes at a time (GCC/Clang vector extensions; plain IEEE fp32 per lane,
// so the bits are those of the scalar formulas):
//  * every row of table 17.2 is one of eight candidate vectors v, or 1 − v;
//  * SUBTRACT and REVERSE_SUBTRACT are ADD with one product negated (IEEE 754 defines x − y as
//    x + (−y), and negation is exact);
//  * MIN/MAX lanes take minNum/maxNum of the operands instead.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__AVX__)
#include <immintrin.h>
#endif

#include <glm/vec4.hpp>

#include "blend/blend_factor.h"
#include "oitref/core/blend_state.h"
#include "oitref/core/unorm.h"

namespace oitref::detail {

typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

inline v4f load4(const glm::vec4& v) {
  v4f r;
  std::memcpy(&r, &v[0], 16);
  return r;
}
inline glm::vec4 store4(v4f v) {
  glm::vec4 r;
  std::memcpy(&r[0], &v, 16);
  return r;
}
inline v4f splat(float x) { return v4f{x, x, x, x}; }
inline v4f select(v4i mask, v4f a, v4f b) { return mask ? a : b; }
// The first Channels of four 8-bit codes (0..255 in 32-bit lanes) into an 8-bit texel. All four
// are narrowed together by two packing instructions and stored as one word: lane by lane (and as
// GCC compiles __builtin_convertvector to bytes), each was extracted, shifted and or-ed into place.
template <int Channels>
inline void storeUnorm8Codes(v4i codes, uint8_t* texel) {
#if defined(__SSE2__)
  if constexpr (Channels == 4) {
    const __m128i words = _mm_packs_epi32(__m128i(codes), __m128i(codes));  // SSE2; exact for 0..255
    const int32_t bytes = _mm_cvtsi128_si32(_mm_packus_epi16(words, words));
    std::memcpy(texel, &bytes, 4);
    return;
  }
#endif
  for (int c = 0; c < Channels; ++c) texel[c] = uint8_t(codes[c]);
}

// Two pixels' four channels side by side (the batch kernels): the same per-lane operations.
typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));
inline v8f select(v8i mask, v8f a, v8f b) { return mask ? a : b; }
template <typename V>
using IntLanesOf = std::conditional_t<sizeof(V) == 16, v4i, v8i>;
template <typename V>
inline V splatLanes(float x) {
  return x - V{};  // x − (+0) keeps −0 (lanes::splat)
}
// Lane `L` of each pixel in all of that pixel's lanes.
template <int L>
inline v4f eachPixelLane(v4f v) {
  return __builtin_shufflevector(v, v, L, L, L, L);
}
template <int L>
inline v8f eachPixelLane(v8f v) {
  return __builtin_shufflevector(v, v, L, L, L, L, L + 4, L + 4, L + 4, L + 4);
}
// A per-channel pattern (four lanes) for every pixel.
inline v4i eachPixel(v4i p, v4i) { return p; }
inline v8i eachPixel(v4i p, v8i) { return __builtin_shufflevector(p, p, 0, 1, 2, 3, 0, 1, 2, 3); }
template <typename V>
inline IntLanesOf<V> eachPixel(v4i p) {
  return eachPixel(p, IntLanesOf<V>{});
}
inline v8f twoPixels(v4f a, v4f b) { return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7); }
inline v4f pixelOf(v8f v, int p) {
  return p == 0 ? __builtin_shufflevector(v, v, 0, 1, 2, 3) : __builtin_shufflevector(v, v, 4, 5, 6, 7);
}

// Clamp to [0,1] with NaN -> 0, as clampUnit: v > 0 ? (v < 1 ? v : 1) : 0.
template <typename V>
inline V clampUnitLanes(V v) {
  return select(v > 0.0f, select(v < 1.0f, v, splatLanes<V>(1.0f)), splatLanes<V>(0.0f));
}
inline v4f clampUnit4(v4f v) { return clampUnitLanes(v); }
inline glm::vec4 clampUnit4(const glm::vec4& v) { return store4(clampUnit4(load4(v))); }

// NaN signs and payloads from arithmetic differ between CPUs (x86's default NaN is negative,
// ARM's positive) and GL does not specify them: a NaN blend result is the canonical quiet NaN.
template <typename V>
inline V canonicalNan(V v) {
  return select(v != v, splatLanes<V>(__builtin_nanf("")), v);
}

typedef double v4d __attribute__((vector_size(32)));

// encodeUnorm (oitref/core/unorm.h) four channels at a time, same bits: after the clamp, a product p
// in [0, 2^52) is rounded to an integer, ties to even, by (p + 2^52) − 2^52 in the default
// rounding mode (for the fp32 product, p < 2^23 and 2^23 does the same in fp32). x86's rounding
// conversions (cvtps2dq, cvtpd2dq) round in that same mode: one instruction for the two additions
// and the truncating conversion, the same integer.
inline v4i encodeUnorm4(v4f v, int bits, UnormRounding rounding) {
  const uint32_t maxCode = (uint32_t(1) << bits) - 1;
#if defined(__SSE2__)
  // clampUnit4 in two instructions: MAXPS gives its second operand, +0, where v is NaN or ±0,
  // and MINPS its first where it is below 1 — the same lanes as the comparisons and selects.
  v = (v4f)_mm_min_ps(_mm_max_ps((__m128)v, _mm_setzero_ps()), _mm_set1_ps(1.0f));
#else
  v = clampUnit4(v);
#endif
  if (rounding == UnormRounding::NvidiaFixed) {  // bits ≤ 12 (X·maxCode < 2^31): the 8-bit kernels
    const int fraction = bits + 4;
    const v4i x = __builtin_convertvector(v * float(1 << fraction), v4i);  // exact scaling, then floor (v ≥ 0)
    return (x * int32_t(maxCode) + ((1 << (fraction - 1)) - 1)) >> fraction;
  }
  if (rounding == UnormRounding::Fp32Product) {
    const v4f p = v * float(maxCode);
#if defined(__SSE2__)
    return (v4i)_mm_cvtps_epi32((__m128)p);
#else
    const v4f twoPow23 = splat(8388608.0f);
    return __builtin_convertvector((p + twoPow23) - twoPow23, v4i);
#endif
  }
#if defined(__AVX__)
  // One VCVTPS2PD of all four lanes (GCC splits __builtin_convertvector into two halves).
  const __m256d p = _mm256_mul_pd(_mm256_cvtps_pd((__m128)v), _mm256_set1_pd(double(maxCode)));
  return (v4i)_mm256_cvtpd_epi32(p);
#else
  const v4d p = __builtin_convertvector(v, v4d) * double(maxCode);
  const v4d twoPow52 = v4d{4503599627370496.0, 4503599627370496.0, 4503599627370496.0, 4503599627370496.0};
  return __builtin_convertvector((p + twoPow52) - twoPow52, v4i);
#endif
}

// IEEE minNum/maxNum; on equality the source (first operand).
template <typename V>
inline V minNum(V s, V d) {
  return select(s != s, d, select(d != d, s, select(d < s, d, s)));
}
template <typename V>
inline V maxNum(V s, V d) {
  return select(s != s, d, select(d != d, s, select(d > s, d, s)));
}

struct CompiledBlend {
  // Lane l of the source factor is candidate row srcRow[l] of blend_factor.h (1 − it where
  // srcOneMinus); srcLanes[k] has all bits set in the lanes that take row k.
  int srcRow[4], dstRow[4];
  v4i srcLanes[8], dstLanes[8];
  unsigned rowsUsed;
  v4i srcOneMinus, dstOneMinus;
  v4i negateSrc, negateDst;  // sign-bit masks for SUBTRACT / REVERSE_SUBTRACT lanes
  v4i minLanes, maxLanes;
  bool anyMinMax;
};

// constexpr, so that a kernel compiled for a known state (target_blender.cpp) folds it away. GCC
// does not allow assigning single lanes of a vector in a constant expression, so the lanes are
// gathered in arrays first.
constexpr CompiledBlend compileBlend(const BlendState& st) {
  CompiledBlend c{};
  int srcLanes[8][4] = {}, dstLanes[8][4] = {};
  int srcOneMinus[4] = {}, dstOneMinus[4] = {}, negateSrc[4] = {}, negateDst[4] = {}, minLanes[4] = {}, maxLanes[4] = {};
  for (int l = 0; l < 4; ++l) {
    const BlendFactor sf = l < 3 ? st.srcRgb : st.srcAlpha, df = l < 3 ? st.dstRgb : st.dstAlpha;
    const BlendEquation eq = l < 3 ? st.equationRgb : st.equationAlpha;
    c.srcRow[l] = factorRow(sf).row;
    c.dstRow[l] = factorRow(df).row;
    srcOneMinus[l] = factorRow(sf).oneMinus ? -1 : 0;
    dstOneMinus[l] = factorRow(df).oneMinus ? -1 : 0;
    negateSrc[l] = eq == BlendEquation::ReverseSubtract ? int32_t(0x80000000u) : 0;
    negateDst[l] = eq == BlendEquation::Subtract ? int32_t(0x80000000u) : 0;
    minLanes[l] = eq == BlendEquation::Min ? -1 : 0;
    maxLanes[l] = eq == BlendEquation::Max ? -1 : 0;
    c.anyMinMax = c.anyMinMax || eq == BlendEquation::Min || eq == BlendEquation::Max;
    srcLanes[c.srcRow[l]][l] = -1;
    dstLanes[c.dstRow[l]][l] = -1;
    c.rowsUsed |= (1u << c.srcRow[l]) | (1u << c.dstRow[l]);
  }
  auto vec = [](const int* a) { return v4i{a[0], a[1], a[2], a[3]}; };
  for (int k = 0; k < 8; ++k) c.srcLanes[k] = vec(srcLanes[k]), c.dstLanes[k] = vec(dstLanes[k]);
  c.srcOneMinus = vec(srcOneMinus), c.dstOneMinus = vec(dstOneMinus);
  c.negateSrc = vec(negateSrc), c.negateDst = vec(negateDst);
  c.minLanes = vec(minLanes), c.maxLanes = vec(maxLanes);
  c.rowsUsed &= ~1u;  // row 0 is zero: contributes nothing to the OR below
  return c;
}

// The blend of lanes that each hold one channel of one pixel, every rule of table 17.2 and §17.3.6
// stated once: `lanes(m)` spreads a per-channel pattern m (lanes R, G, B, A of CompiledBlend) over
// the lanes as their channels lie; `alphaLanes` marks the lanes that hold an alpha channel; sa and
// ad are each lane's pixel's source and destination alpha, c and ca the constant's channel and
// alpha. Each lane gets the operations of the scalar formulas, whatever its neighbours hold.
template <typename V, typename Lanes>
[[gnu::always_inline]] inline V blendLanes(const CompiledBlend& cb, const Lanes& lanes, IntLanesOf<V> alphaLanes, V s,
                                            V sa, V d, V ad, V c, V ca) {
  using I = IntLanesOf<V>;
  const V one = splatLanes<V>(1.0f);
  I sRowBits{}, dRowBits{};
  auto take = [&](int k, V row) {
    sRowBits |= (I)row & lanes(cb.srcLanes[k]);
    dRowBits |= (I)row & lanes(cb.dstLanes[k]);
  };
  if (cb.rowsUsed & (1u << 1)) take(1, s);
  if (cb.rowsUsed & (1u << 2)) take(2, select(alphaLanes, ad, d));
  if (cb.rowsUsed & (1u << 3)) take(3, sa);
  if (cb.rowsUsed & (1u << 4)) take(4, ad);
  if (cb.rowsUsed & (1u << 5)) take(5, c);
  if (cb.rowsUsed & (1u << 6)) take(6, ca);
  if (cb.rowsUsed & (1u << 7)) {
    const V oneMinusAd = one - ad;
    take(7, select(alphaLanes, one, select(sa < oneMinusAd, sa, oneMinusAd)));
  }
  const V sRow = (V)sRowBits, dRow = (V)dRowBits;
  const V sf = select(lanes(cb.srcOneMinus), one - sRow, sRow);
  const V df = select(lanes(cb.dstOneMinus), one - dRow, dRow);
  const V a = (V)((I)(s * sf) ^ lanes(cb.negateSrc));
  const V b = (V)((I)(d * df) ^ lanes(cb.negateDst));
  V r = a + b;
  if (cb.anyMinMax) r = select(lanes(cb.minLanes), minNum(s, d), select(lanes(cb.maxLanes), maxNum(s, d), r));
  return canonicalNan(r);
}

// A pixel's four channels in four lanes, or two pixels' in eight (the batch kernels).
// `c` must already be clamped for fixed-point targets (done once per draw by the callers).
template <typename V>
[[gnu::always_inline]] inline V blendValues(const CompiledBlend& cb, V s, V d, V c, bool fixedPoint,
                                             bool targetHasAlpha) {
  if (fixedPoint) {
    s = clampUnitLanes(s);
    d = clampUnitLanes(d);
  }
  const V ad = targetHasAlpha ? eachPixelLane<3>(d) : splatLanes<V>(1.0f);
  const V r = blendLanes<V>(cb, [](v4i m) { return eachPixel<V>(m); }, eachPixel<V>(v4i{0, 0, 0, -1}), s,
                            eachPixelLane<3>(s), d, ad, c, eachPixelLane<3>(c));
  return fixedPoint ? clampUnitLanes(r) : r;
}

// Eight lanes of a float target with Channels = 1 or 2 (no alpha): lane l holds channel
// l mod Channels of pixel l / Channels (gatherLanes), `sa` each lane's pixel's source alpha;
// the destination alpha is 1. Four to eight pixels at once where blendValues takes two.
template <int Channels>
[[gnu::always_inline]] inline v8f blendChannelLanes(const CompiledBlend& cb, v8f s, v8f sa, v8f d, v4f constant) {
  static_assert(Channels == 1 || Channels == 2);
  auto lanes = [](v4i m) {
    if constexpr (Channels == 1) return __builtin_shufflevector(m, m, 0, 0, 0, 0, 0, 0, 0, 0);
    else return __builtin_shufflevector(m, m, 0, 1, 0, 1, 0, 1, 0, 1);
  };
  const v8f c = Channels == 1 ? __builtin_shufflevector(constant, constant, 0, 0, 0, 0, 0, 0, 0, 0)
                              : __builtin_shufflevector(constant, constant, 0, 1, 0, 1, 0, 1, 0, 1);
  const v8f ca = __builtin_shufflevector(constant, constant, 3, 3, 3, 3, 3, 3, 3, 3);
  return blendLanes<v8f>(cb, lanes, v8i{}, s, sa, d, splatLanes<v8f>(1.0f), c, ca);
}

}  // namespace oitref::detail
