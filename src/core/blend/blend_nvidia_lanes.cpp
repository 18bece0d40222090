// NVIDIA's float blend of a draw's usual fragments, four channels in vector lanes
// (nvidiaUsualFloatKernel, blend_nvidia.h). The rules are blend_nvidia.h's; blendNvidia is the
// oracle and takes every fragment outside the usual ones.
#include <algorithm>
#include <cstring>

#include "blend/blend_nvidia.h"
#include "blend/nvidia_blender_sum.h"
#include "format/fp16_inline.h"
#include "oitref/core/lanes.h"

namespace oitref::detail {
namespace {

using lanes::f4;
using lanes::i4;
using lanes::d4;

// Lanes whose float is a non-zero, finite number with an exponent field neither 0 nor all ones.
i4 normalNonZero(f4 x) {
  const i4 e = ((i4)x >> 23) & 0xff;
  return (e != 0) & (e != 0xff);
}
bool anyLane(i4 m) {
  uint64_t half[2];
  std::memcpy(half, &m, 16);
  return (half[0] | half[1]) != 0;
}
f4 splat4(float v) { return f4{v, v, v, v}; }
f4 select4(i4 mask, f4 a, f4 b) { return (f4)(((i4)a & mask) | ((i4)b & ~mask)); }

// fp32 → fp16 → fp32 in four lanes, rounding toward zero or to nearest even.
template <bool kTowardZero>
f4 throughHalf(f4 x) {
  return roundThroughHalf4(x, kTowardZero ? Rounding::TowardZero : Rounding::NearestEven);
}

// oneMinus in four lanes (operands normal: no NaN).
template <bool kFp32>
f4 oneMinus4(f4 x) {
  if constexpr (kFp32) return 1.0f - x;
  else return throughHalf<false>(__builtin_convertvector(1.0 - __builtin_convertvector(x, d4), f4));
}

// factorValue in four lanes, lane c the factor of channel c (lane 3 the alpha channel's).
template <bool kFp32>
f4 factorLanes(BlendFactor factor, f4 s, f4 d, float da, f4 k) {
  switch (factor) {
    case BlendFactor::Zero: return splat4(0.0f);
    case BlendFactor::One: return splat4(1.0f);
    case BlendFactor::SrcColor: return s;
    case BlendFactor::OneMinusSrcColor: return oneMinus4<kFp32>(s);
    case BlendFactor::DstColor: return d;
    case BlendFactor::OneMinusDstColor: return oneMinus4<kFp32>(d);
    case BlendFactor::SrcAlpha: return splat4(s[3]);
    case BlendFactor::OneMinusSrcAlpha: return oneMinus4<kFp32>(splat4(s[3]));
    case BlendFactor::DstAlpha: return splat4(da);
    case BlendFactor::OneMinusDstAlpha: return oneMinus4<kFp32>(splat4(da));
    case BlendFactor::ConstantColor: return k;
    case BlendFactor::OneMinusConstantColor: return oneMinus4<kFp32>(k);
    case BlendFactor::ConstantAlpha: return splat4(k[3]);
    case BlendFactor::OneMinusConstantAlpha: return oneMinus4<kFp32>(splat4(k[3]));
    case BlendFactor::SrcAlphaSaturate: {  // minNum of two normal numbers: their minimum
      const float m = std::min(s[3], oneMinus4<kFp32>(splat4(da))[0]);
      return f4{m, m, m, 1.0f};
    }
  }
  return splat4(0.0f);
}
// Lanes 0–2 of the colour channels' factor, lane 3 of the alpha channel's.
template <bool kFp32>
f4 factorsOf(const BlendFactor* kinds, f4 s, f4 d, float da, f4 k) {
  f4 f = factorLanes<kFp32>(kinds[0], s, d, da, k);
  f[3] = kinds[1] == kinds[0] ? f[3] : factorLanes<kFp32>(kinds[1], s, d, da, k)[3];
  return f;
}

// frexp's exponent of normal floats.
i4 exponents(f4 x) { return (((i4)x >> 23) & 0xff) - 126; }

// blendFloat four channels at once, on an fp32 or fp16 target of kChannels channels that the draw
// writes whole, for the usual fragment: a non-zero source alpha, every source and destination
// channel and every evaluated factor finite and not denormal, at most one of a channel's two
// terms zero, and MIN/MAX on non-zero operands. Then none of blendFloat's special cases arise
// (DAZ, NaN, the sign of a zero sum, the rules for As = 0), and blenderSum gives its bits; any
// other fragment goes to blendFloat itself. The test "nvidia: the planned kernels give
// blendNvidia's bits" holds them together. Lanes beyond the target's channels compute ones.
template <bool kFp32, int kChannels>
void fastFloat(const NvidiaBlendPlan& p, const glm::vec4& source, uint8_t* texel) {
  const i4 used{0, kChannels > 1 ? -1 : 0, kChannels > 2 ? -1 : 0, kChannels > 3 ? -1 : 0};
  const i4 channel = used | i4{-1, 0, 0, 0};
  const f4 raw{source[0], source[1], source[2], source[3]};
  const f4 s = kFp32 ? raw : throughHalf<true>(raw);  // as the blend reads it
  f4 d = splat4(1.0f);
  if constexpr (kFp32) {
    std::memcpy(&d, texel, 4 * kChannels);
  } else {
    uint16_t h[4] = {0x3c00, 0x3c00, 0x3c00, 0x3c00};
    std::memcpy(h, texel, 2 * kChannels);
    for (int c = 0; c < 4; ++c) d[c] = decodeHalfInline(h[c]);
  }
  const NvidiaBlendPlan::Lanes& L = p.lanes;
  auto lanesOf = [](const int32_t* v) { return i4{v[0], v[1], v[2], v[3]}; };
  const i4 alphaLane{0, 0, 0, -1}, minMax = lanesOf(L.minMax) & channel;
  const i4 blended = channel & ~minMax;  // the channels that sum two terms
  // Usual operands: finite and not denormal; zero only where a term may be (the source alpha,
  // which the rules for As = 0 read, and MIN/MAX, which order ±0, never).
  const i4 sZero = (i4)(s == 0.0f), dZero = (i4)(d == 0.0f);
  const i4 sUsual = normalNonZero(s) | (sZero & ~alphaLane & ~minMax), dUsual = normalNonZero(d) | (dZero & ~minMax);
  if (anyLane(~sUsual & (channel | alphaLane)) || anyLane(~dUsual & channel))
    return blendNvidia(p.format, p.state, p.constant, source, p.mask, texel);
  // leavesDestination with As ≠ 0: every channel adds or reverse-subtracts, its source term is zero
  // (ZERO, or a zero source) and its destination factor is one (ONE, or ONE_MINUS_SRC_COLOR of a
  // zero source).
  const i4 foldA = lanesOf(L.foldSource), foldB = lanesOf(L.foldDestination);
  const i4 leaves = lanesOf(L.addLike) & (foldA | sZero) & (lanesOf(L.destinationOne) | (lanesOf(L.oneIfSourceZero) & sZero));
  if (!anyLane(~leaves & channel)) return;
  const float da = kChannels == 4 ? d[3] : 1.0f;
  const f4 k{p.convertedConstant[0], p.convertedConstant[1], p.convertedConstant[2], p.convertedConstant[3]};
  const f4 fsEvaluated = factorsOf<kFp32>(L.source, s, d, da, k), fdEvaluated = factorsOf<kFp32>(L.destination, s, d, da, k);
  const i4 fsZero = (i4)(fsEvaluated == 0.0f), fdZero = (i4)(fdEvaluated == 0.0f);
  if (anyLane(~(normalNonZero(fsEvaluated) | fsZero) & blended & ~foldA) ||
      anyLane(~(normalNonZero(fdEvaluated) | fdZero) & blended & ~foldB))
    return blendNvidia(p.format, p.state, p.constant, source, p.mask, texel);
  // A zero term (left out, a zero value or a zero factor) has the product 0 and no exponent; two
  // zero terms take blendFloat's rules for the sign of their sum.
  const i4 zeroA = blended & (foldA | sZero | fsZero), zeroB = blended & (foldB | dZero | fdZero);
  if (anyLane(zeroA & zeroB)) return blendNvidia(p.format, p.state, p.constant, source, p.mask, texel);
  // Lanes that sum nothing (no channel, or MIN/MAX) compute 1·1 + 1·1 and are not used.
  const f4 one = splat4(1.0f), zero = splat4(0.0f);
  const f4 sc = select4(blended, s, one), dc = select4(blended, d, one);
  const f4 fs = select4(blended, select4(zeroA, zero, fsEvaluated), one);
  const f4 fd = select4(blended, select4(zeroB, zero, fdEvaluated), one);
  const d4 signA{L.signSource[0], L.signSource[1], L.signSource[2], L.signSource[3]};
  const d4 signB{L.signDestination[0], L.signDestination[1], L.signDestination[2], L.signDestination[3]};
  const d4 pa = __builtin_convertvector(sc, d4) * __builtin_convertvector(fs, d4) * signA;  // exact
  const d4 pb = __builtin_convertvector(dc, d4) * __builtin_convertvector(fd, d4) * signB;
  // The larger exponent estimate of the non-zero terms.
  const i4 none = i4{} - 100000;
  const i4 estA = ((exponents(sc) + exponents(fs)) & ~zeroA) | (none & zeroA);
  const i4 estB = ((exponents(dc) + exponents(fd)) & ~zeroB) | (none & zeroB);
  const d4 sum = nvidia_sum::blenderSum<d4>(pa, pb, estA > estB ? estA : estB, kFp32 ? 24 : 11, kFp32 ? -149 : -24);
  f4 out = __builtin_convertvector(sum, f4);  // to nearest even, as float(value)
  // MIN/MAX: minNum/maxNum of two numbers.
  const i4 isMin = lanesOf(L.isMin);
  const f4 extreme = select4(~(isMin ^ (i4)(s < d)), s, d);
  out = select4(blended, out, extreme);
  if constexpr (kFp32) {
    const i4 bits = (i4)out;
    const i4 sign = bits & int32_t(0x80000000);
    out = select4((bits & 0x7fffffff) < 0x00800000, (f4)sign, out);  // FTZ
    std::memcpy(texel, &out, 4 * kChannels);
  } else {
    uint16_t h[4];
    encodeHalf4Inline(out, Rounding::NearestEven, h);
    std::memcpy(texel, h, 2 * kChannels);
  }
}

}  // namespace

NvidiaBlendFn nvidiaUsualFloatKernel(bool fp32, int channels) {
  if (fp32) return channels == 4 ? fastFloat<true, 4> : channels == 2 ? fastFloat<true, 2> : fastFloat<true, 1>;
  return channels == 4 ? fastFloat<false, 4> : channels == 2 ? fastFloat<false, 2> : fastFloat<false, 1>;
}

}  // namespace oitref::detail
