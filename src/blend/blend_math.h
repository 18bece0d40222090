// The GL 4.6 §17.3.6 blend arithmetic on decoded fp32 values, used by every path that blends in
// floating point (the generic path and the per-format fast paths of target_blender.cpp), so the
// rule exists once. Rules: include/oitref/blend.h.
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

#include <glm/vec4.hpp>

#include "blend/blend_factor.h"
#include "oitref/blend_state.h"
#include "oitref/unorm.h"

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

// Clamp to [0,1] with NaN -> 0, as clampUnit: v > 0 ? (v < 1 ? v : 1) : 0.
inline v4f clampUnit4(v4f v) { return select(v > 0.0f, select(v < 1.0f, v, splat(1.0f)), splat(0.0f)); }
inline glm::vec4 clampUnit4(const glm::vec4& v) { return store4(clampUnit4(load4(v))); }

// NaN signs and payloads from arithmetic differ between CPUs (x86's default NaN is negative,
// ARM's positive) and GL does not specify them: a NaN blend result is the canonical quiet NaN.
inline v4f canonicalNan(v4f v) { return select(v != v, splat(__builtin_nanf("")), v); }

typedef double v4d __attribute__((vector_size(32)));

// encodeUnorm (oitref/unorm.h) four channels at a time, same bits: after the clamp, a product p
// in [0, 2^52) is rounded to an integer, ties to even, by (p + 2^52) − 2^52 in the default
// rounding mode (for the fp32 product, p < 2^23 and 2^23 does the same in fp32).
inline v4i encodeUnorm4(v4f v, int bits, UnormRounding rounding) {
  const uint32_t maxCode = (uint32_t(1) << bits) - 1;
  v = clampUnit4(v);
  if (rounding == UnormRounding::NvidiaFixed) {  // bits ≤ 12 (X·maxCode < 2^31): the 8-bit kernels
    const int fraction = bits + 4;
    const v4i x = __builtin_convertvector(v * float(1 << fraction), v4i);  // exact scaling, then floor (v ≥ 0)
    return (x * int32_t(maxCode) + ((1 << (fraction - 1)) - 1)) >> fraction;
  }
  if (rounding == UnormRounding::Fp32Product) {
    const v4f p = v * float(maxCode);
    const v4f twoPow23 = splat(8388608.0f);
    return __builtin_convertvector((p + twoPow23) - twoPow23, v4i);
  }
  const v4d p = __builtin_convertvector(v, v4d) * double(maxCode);
  const v4d twoPow52 = v4d{4503599627370496.0, 4503599627370496.0, 4503599627370496.0, 4503599627370496.0};
  return __builtin_convertvector((p + twoPow52) - twoPow52, v4i);
}

// IEEE minNum/maxNum; on equality the source (first operand).
inline v4f minNum(v4f s, v4f d) { return select(s != s, d, select(d != d, s, select(d < s, d, s))); }
inline v4f maxNum(v4f s, v4f d) { return select(s != s, d, select(d != d, s, select(d > s, d, s))); }

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

// `c` must already be clamped for fixed-point targets (done once per draw by the callers).
[[gnu::always_inline]] inline v4f blendValues(const CompiledBlend& cb, v4f s, v4f d, v4f c, bool fixedPoint,
                                               bool targetHasAlpha) {
  if (fixedPoint) {
    s = clampUnit4(s);
    d = clampUnit4(d);
  }
  const float ad = targetHasAlpha ? d[3] : 1.0f;
  v4i sRowBits = v4i{0, 0, 0, 0}, dRowBits = v4i{0, 0, 0, 0};
  auto take = [&](int k, v4f row) {
    sRowBits |= (v4i)row & cb.srcLanes[k];
    dRowBits |= (v4i)row & cb.dstLanes[k];
  };
  if (cb.rowsUsed & (1u << 1)) take(1, s);
  if (cb.rowsUsed & (1u << 2)) take(2, v4f{d[0], d[1], d[2], ad});
  if (cb.rowsUsed & (1u << 3)) take(3, splat(s[3]));
  if (cb.rowsUsed & (1u << 4)) take(4, splat(ad));
  if (cb.rowsUsed & (1u << 5)) take(5, c);
  if (cb.rowsUsed & (1u << 6)) take(6, splat(c[3]));
  if (cb.rowsUsed & (1u << 7)) {
    const float oneMinusAd = 1.0f - ad;
    const float f = s[3] < oneMinusAd ? s[3] : oneMinusAd;
    take(7, v4f{f, f, f, 1.0f});
  }
  const v4f sRow = (v4f)sRowBits, dRow = (v4f)dRowBits;
  const v4f one = splat(1.0f);
  const v4f sf = select(cb.srcOneMinus, one - sRow, sRow);
  const v4f df = select(cb.dstOneMinus, one - dRow, dRow);
  const v4f a = (v4f)((v4i)(s * sf) ^ cb.negateSrc);
  const v4f b = (v4f)((v4i)(d * df) ^ cb.negateDst);
  v4f r = a + b;
  if (cb.anyMinMax) r = select(cb.minLanes, minNum(s, d), select(cb.maxLanes, maxNum(s, d), r));
  r = canonicalNan(r);
  return fixedPoint ? clampUnit4(r) : r;
}

}  // namespace oitref::detail
