#include "blend/blend_nvidia.h"

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstring>

#include "blend/nvidia_blender_sum.h"
#include "format/fp16_inline.h"
#include "format/packed_layout.h"
#include "format/unorm_rescale.h"
#include "oitref/core/fp16.h"
#include "oitref/core/profile.h"
#include "oitref/core/unorm.h"

namespace oitref::detail {
namespace {

bool isMinMax(BlendEquation e) { return e == BlendEquation::Min || e == BlendEquation::Max; }

// ---- UNORM targets: exact arithmetic on codes --------------------------------------------------

// kBits: the width of a non-packed target known when compiled (8, 16: its divisions by 2^b − 1
// become multiplications), or 0 for any target.
template <int kBits>
void blendUnorm(const Format& f, const BlendState& st, const glm::vec4& constant, const glm::vec4& source, unsigned mask,
                uint8_t* texel) {
  const bool packed = kBits == 0 && f.id == FormatId::RGB10A2;
  const int bits = kBits ? kBits : packed ? 10 : f.unormBits(0), bytes = bits / 8;
  const int64_t M = (int64_t(1) << bits) - 1;
  int64_t s[4], k[4], d[4] = {0, 0, 0, M};
  uint32_t word = 0;
  if (packed) std::memcpy(&word, texel, 4);
  for (int c = 0; c < 4; ++c) {
    s[c] = encodeUnorm(source[c], bits, UnormRounding::NvidiaFixed);
    k[c] = encodeUnorm(constant[c], bits, UnormRounding::NvidiaFixed);
    if (c >= f.channels) continue;
    if (packed) {
      const uint32_t code = (word >> kRgb10a2Shift[c]) & ((1u << kRgb10a2Bits[c]) - 1);
      d[c] = c == 3 ? int64_t(code) * 341 : int64_t(code);  // 1023 = 3·341: a/3 as a 10-bit code
    } else {
      uint32_t code = 0;
      std::memcpy(&code, texel + c * bytes, size_t(bytes));
      d[c] = code;
    }
  }
  const int64_t da = f.hasAlpha() ? d[3] : M;
  auto factor = [&](BlendFactor factor, int lane) -> int64_t {
    const int64_t dLane = lane < 3 ? d[lane] : da;
    switch (factor) {
      case BlendFactor::Zero: return 0;
      case BlendFactor::One: return M;
      case BlendFactor::SrcColor: return s[lane];
      case BlendFactor::OneMinusSrcColor: return M - s[lane];
      case BlendFactor::DstColor: return dLane;
      case BlendFactor::OneMinusDstColor: return M - dLane;
      case BlendFactor::SrcAlpha: return s[3];
      case BlendFactor::OneMinusSrcAlpha: return M - s[3];
      case BlendFactor::DstAlpha: return da;
      case BlendFactor::OneMinusDstAlpha: return M - da;
      case BlendFactor::ConstantColor: return k[lane];
      case BlendFactor::OneMinusConstantColor: return M - k[lane];
      case BlendFactor::ConstantAlpha: return k[3];
      case BlendFactor::OneMinusConstantAlpha: return M - k[3];
      case BlendFactor::SrcAlphaSaturate: return lane < 3 ? std::min(s[3], M - da) : M;
    }
    return 0;
  };
  for (int c = 0; c < f.channels; ++c) {
    if (!(mask >> c & 1)) continue;
    const bool alpha = c == 3;
    const BlendEquation eq = alpha ? st.equationAlpha : st.equationRgb;
    const int64_t dc = alpha ? da : d[c];
    int64_t code;
    if (eq == BlendEquation::Min) code = std::min(s[c], dc);
    else if (eq == BlendEquation::Max) code = std::max(s[c], dc);
    else {
      const int64_t a = s[c] * factor(alpha ? st.srcAlpha : st.srcRgb, c), b = dc * factor(alpha ? st.dstAlpha : st.dstRgb, c);
      const int64_t n = std::clamp(eq == BlendEquation::Add ? a + b : eq == BlendEquation::Subtract ? a - b : b - a,
                                   int64_t(0), M * M);
      code = (2 * n + M) / (2 * M);  // n/M to the nearest integer; M is odd, so no ties
    }
    if (packed) {
      const uint32_t stored = alpha ? nvidiaAlpha2From10(uint32_t(code)) : uint32_t(code);
      word = (word & ~(((1u << kRgb10a2Bits[c]) - 1) << kRgb10a2Shift[c])) | (stored << kRgb10a2Shift[c]);
    } else {
      const uint32_t v = uint32_t(code);
      std::memcpy(texel + c * bytes, &v, size_t(bytes));
    }
  }
  if (packed) std::memcpy(texel, &word, 4);
}

// ---- float targets: the two-product adder ------------------------------------------------------

struct FloatTarget {
  int p;            // significand bits of the blend arithmetic
  bool fp32;        // DAZ/FTZ; else fp16 arithmetic (r11g11b10f narrows afterwards)
  int minExponent;  // exponent of the smallest denormal's last place (fp16: −24)
};

float daz(float x) { return std::fpclassify(x) == FP_SUBNORMAL ? std::copysign(0.0f, x) : x; }
float toHalfTowardZero(float x) { return decodeHalfInline(encodeHalfInline(x, Rounding::TowardZero)); }
float toHalfNearest(double x) { return decodeHalfInline(encodeHalfInline(float(x), Rounding::NearestEven)); }  // x has ≤ 24 bits

const float kGpuNan = std::bit_cast<float>(0x7fffffffu);  // the NaN the GPU computes: every bit set but the sign

// 1 − x in the blend precision; a NaN x gives the GPU's NaN (positive).
float oneMinus(const FloatTarget& t, float x) {
  if (std::isnan(x)) return kGpuNan;
  return t.fp32 ? 1.0f - x : toHalfNearest(1.0 - double(x));
}

// IEEE minNum: a NaN operand loses to a number; −0 orders below +0.
float minNum(float a, float b) {
  if (std::isnan(a)) return b;
  if (std::isnan(b)) return a;
  return a < b || (a == b && std::signbit(a)) ? a : b;
}

// frexp's exponent of a finite non-zero x (x = m·2^e, ½ ≤ |m| < 1), from its bits: libm's frexp,
// ldexp and trunc were most of a blend's time.
int exponentOf(double x) {
  const int biased = int((std::bit_cast<uint64_t>(x) >> 52) & 0x7ff);
  if (biased != 0) return biased - 1022;
  return exponentOf(x * 0x1p64) - 64;  // a denormal double (the operands are floats: never)
}

struct Term {
  float value, factor;
  bool negate;
  bool folded;  // the factor is ZERO: the term is not computed
  double product() const {
    if (zero()) return 0.0;  // zero times anything, inf and NaN included, is zero
    const double p = double(value) * double(factor);  // exact: at most 48 significant bits
    return negate ? -p : p;
  }
  bool zero() const { return folded || value == 0.0f || factor == 0.0f; }
};

// s·Sf ± d·Df as the blender sums it; `zeroNegative` is the sign of a sum of two exact zeros.
double twoProductSum(const FloatTarget& t, const Term& a, const Term& b, bool zeroNegative) {
  const double pa = a.product(), pb = b.product();
  if (!std::isfinite(pa) || !std::isfinite(pb) || std::isnan(pa + pb)) return pa + pb;
  if (a.zero() && b.zero()) return zeroNegative ? -0.0 : 0.0;
  int e = INT_MIN;
  if (!a.zero()) e = exponentOf(a.value) + exponentOf(a.factor);
  if (!b.zero()) e = std::max(e, exponentOf(b.value) + exponentOf(b.factor));
  return nvidia_sum::blenderSum<double>(pa, pb, e, t.p, t.minExponent);  // a zero term's product is 0
}

// The GPU skips the blend, leaving every bit of the destination as it was, when the source cannot
// change a destination in [0, 1]: in every written channel the equation adds or reverse-subtracts,
// the source term is zero (factor ZERO, a zero source value, or a source-alpha factor with As = 0)
// and the destination factor is one (ONE, or ONE_MINUS_SRC_ALPHA / _COLOR of a zero source).
// Visible only where the destination holds values outside [0, 1], infinities or NaN.
bool leavesDestination(const Format& f, const BlendState& st, const glm::vec4& s, const glm::vec4& k) {
  const bool alphaZero = s[3] == 0.0f;
  // A non-finite constant (any channel) or source (the target's channels, and alpha) prevents it.
  for (int c = 0; c < 4; ++c)
    if (!std::isfinite(k[c]) || ((c < f.channels || c == 3) && !std::isfinite(s[c]))) return false;
  for (int c = 0; c < f.channels; ++c) {
    const bool alpha = c == 3;
    const BlendEquation eq = alpha ? st.equationAlpha : st.equationRgb;
    const BlendFactor sf = alpha ? st.srcAlpha : st.srcRgb, df = alpha ? st.dstAlpha : st.dstRgb;
    if (eq != BlendEquation::Add && eq != BlendEquation::ReverseSubtract) return false;
    const bool sourceZero = sf == BlendFactor::Zero || s[c] == 0.0f ||
                            ((sf == BlendFactor::SrcAlpha || (sf == BlendFactor::SrcAlphaSaturate && !alpha)) && alphaZero);
    const bool destinationOne = df == BlendFactor::One || (df == BlendFactor::OneMinusSrcAlpha && alphaZero) ||
                                (df == BlendFactor::OneMinusSrcColor && s[c] == 0.0f);
    if (!sourceZero || !destinationOne) return false;
  }
  return true;
}

// A factor's value in the blend precision for channel `lane`: s, d and k as converted, da the
// destination alpha (1 without an alpha channel).
float factorValue(const FloatTarget& t, BlendFactor factor, int lane, const glm::vec4& s, const glm::vec4& d, float da,
                  const glm::vec4& k) {
  const float dLane = lane < 3 ? d[lane] : da;
  switch (factor) {
    case BlendFactor::Zero: return 0.0f;
    case BlendFactor::One: return 1.0f;
    case BlendFactor::SrcColor: return s[lane];
    case BlendFactor::OneMinusSrcColor: return oneMinus(t, s[lane]);
    case BlendFactor::DstColor: return dLane;
    case BlendFactor::OneMinusDstColor: return oneMinus(t, dLane);
    case BlendFactor::SrcAlpha: return s[3];
    case BlendFactor::OneMinusSrcAlpha: return oneMinus(t, s[3]);
    case BlendFactor::DstAlpha: return da;
    case BlendFactor::OneMinusDstAlpha: return oneMinus(t, da);
    case BlendFactor::ConstantColor: return k[lane];
    case BlendFactor::OneMinusConstantColor: return oneMinus(t, k[lane]);
    case BlendFactor::ConstantAlpha: return k[3];
    case BlendFactor::OneMinusConstantAlpha: return oneMinus(t, k[3]);
    case BlendFactor::SrcAlphaSaturate: return lane == 3 ? 1.0f : minNum(s[3], oneMinus(t, da));
  }
  return 0.0f;
}

bool readsDestination(BlendFactor f) {
  return f == BlendFactor::DstColor || f == BlendFactor::OneMinusDstColor || f == BlendFactor::DstAlpha ||
         f == BlendFactor::OneMinusDstAlpha;
}

// Whether one half of the blend (the colour channels, or alpha) leaves the destination out: its
// equation adds or subtracts, its destination factor is ZERO, or SRC_COLOR / SRC_ALPHA (and, where
// `saturateCounts`, SRC_ALPHA_SATURATE) of a zero source, and its source term needs no destination
// value (its factor reads none, or the source is zero). `sourceZero`: the half's own source
// channels are zero; in the alpha half SRC_COLOR is As.
bool leavesDestinationOut(BlendEquation eq, BlendFactor sf, BlendFactor df, bool sourceZero, bool alphaZero,
                          bool saturateCounts = false) {
  if (isMinMax(eq)) return false;
  const bool destinationTermZero = df == BlendFactor::Zero || (df == BlendFactor::SrcColor && sourceZero) ||
                                   ((df == BlendFactor::SrcAlpha ||
                                     (saturateCounts && df == BlendFactor::SrcAlphaSaturate)) && alphaZero);
  return destinationTermZero && (sourceZero || !readsDestination(sf));
}

void blendFloat(const Format& f, const BlendState& st, const glm::vec4& constant, const glm::vec4& source, unsigned mask,
                uint8_t* texel) {
  const bool fp32 = f.encoding() == ChannelEncoding::Float32;
  const FloatTarget t{fp32 ? 24 : 11, fp32, fp32 ? -149 : -24};
  const glm::vec4 stored = decodeTexel(f, texel);
  glm::vec4 s(0.0f), k(0.0f), d(0.0f);
  for (int c = 0; c < 4; ++c) {
    s[c] = t.fp32 ? daz(source[c]) : toHalfTowardZero(source[c]);
    k[c] = t.fp32 ? daz(constant[c]) : toHalfTowardZero(constant[c]);
    d[c] = t.fp32 ? daz(stored[c]) : stored[c];
  }
  const float da = f.hasAlpha() ? d[3] : 1.0f;
  auto factor = [&](BlendFactor factor, int lane) { return factorValue(t, factor, lane, s, d, da, k); };
  if (leavesDestination(f, st, s, k)) return;
  // The source colour (as converted) is zero in the target's colour channels.
  bool sourceColourZero = true;
  for (int c = 0; c < std::min(f.channels, 3); ++c) sourceColourZero = sourceColourZero && s[c] == 0.0f;
  // SRC_ALPHA_SATURATE as the colour destination factor is zero when As is zero and the alpha
  // destination factor evaluates to zero (ZERO, or SRC_ALPHA / SRC_COLOR of that zero As).
  const bool saturateDestinationZero = s[3] == 0.0f && factor(st.dstAlpha, 3) == 0.0f;
  // Which factors' signs stay out of a zero source term (docs/rules.md); asked only when both
  // terms are exact zeros. For 1 − destination factors, each half of the blend (colour, alpha)
  // that leaves the destination out decides the other half's (`alphastate`): the source as the
  // fragment wrote it. Without an alpha channel the colour half's own destination term decides
  // (`noalpha`): the converted source colour, and SRC_ALPHA_SATURATE with As = 0 counts, while
  // factors zero only through the implied Ad = 1 do not.
  auto factorSignDropsOut = [&](BlendFactor sf, bool alpha) {
    if (sf == BlendFactor::DstColor) return sourceColourZero;
    if (sf != BlendFactor::OneMinusDstColor && sf != BlendFactor::OneMinusDstAlpha) return false;
    bool rawColourZero = true;
    for (int c = 0; c < std::min(f.channels, 3); ++c) rawColourZero = rawColourZero && source[c] == 0.0f;
    const bool rawAlphaZero = source[3] == 0.0f;
    if (alpha) return leavesDestinationOut(st.equationRgb, st.srcRgb, st.dstRgb, rawColourZero, rawAlphaZero);
    if (!f.hasAlpha())
      return leavesDestinationOut(st.equationRgb, st.srcRgb, st.dstRgb, sourceColourZero, rawAlphaZero, true) &&
             sourceColourZero;
    return leavesDestinationOut(st.equationAlpha, st.srcAlpha, st.dstAlpha, rawAlphaZero, rawAlphaZero) &&
           sourceColourZero;
  };
  glm::vec4 out = stored;
  for (int c = 0; c < f.channels; ++c) {
    const bool alpha = c == 3;
    const BlendEquation eq = alpha ? st.equationAlpha : st.equationRgb;
    const float dc = alpha ? da : d[c];
    double value;
    if (isMinMax(eq)) {
      // minNum/maxNum: a NaN operand loses to a number; −0 orders below +0.
      const bool sBelow = s[c] < dc || (s[c] == dc && std::signbit(s[c]) && !std::signbit(dc));
      if (std::isnan(s[c])) value = dc;
      else if (std::isnan(dc)) value = s[c];
      else value = (eq == BlendEquation::Min) == sBelow ? s[c] : dc;
    } else {
      const BlendFactor sf = alpha ? st.srcAlpha : st.srcRgb, df = alpha ? st.dstAlpha : st.dstRgb;
      const Term a{s[c], factor(sf, c), eq == BlendEquation::ReverseSubtract, sf == BlendFactor::Zero};
      const float dstFactor = df == BlendFactor::SrcAlphaSaturate && !alpha && saturateDestinationZero ? 0.0f : factor(df, c);
      const Term b{dc, dstFactor, eq == BlendEquation::Subtract, df == BlendFactor::Zero};
      // Sign of a sum of two exact zeros (docs/rules.md): the destination term's when the
      // destination value is zero and its factor is not, else the source term's.
      bool zeroNegative;
      if (b.value == 0.0f && b.factor != 0.0f)
        zeroNegative = (std::signbit(b.value) != std::signbit(b.factor)) != b.negate;
      else  // the source term's, some factors' signs left out
        zeroNegative = (std::signbit(a.value) != (factorSignDropsOut(sf, alpha) ? false : std::signbit(a.factor))) != a.negate;
      value = twoProductSum(t, a, b, zeroNegative);
    }
    if (std::isnan(value)) {
      out[c] = kGpuNan;
    } else if (t.fp32) {
      const float r = float(value);
      out[c] = std::fabs(r) < 0x1p-126f ? std::copysign(0.0f, r) : r;  // FTZ
    } else {
      out[c] = toHalfNearest(value);  // r11g11b10f: encodeTexel then narrows toward zero
    }
  }
  uint8_t encoded[16];
  encodeTexel(f, out, nvidiaProfile(), encoded);
  mergeTexelChannels(f, encoded, texel, mask);
}

void oracle(const NvidiaBlendPlan& p, const glm::vec4& source, uint8_t* texel) {
  blendNvidia(p.format, p.state, p.constant, source, p.mask, texel);
}
template <int kBits>
void unormOf(const NvidiaBlendPlan& p, const glm::vec4& source, uint8_t* texel) {
  blendUnorm<kBits>(p.format, p.state, p.constant, source, p.mask, texel);
}

}  // namespace

void blendNvidia(const Format& format, const BlendState& state, const glm::vec4& constant, const glm::vec4& source,
                 unsigned mask, uint8_t* texel) {
  if (format.isUnorm()) blendUnorm<0>(format, state, constant, source, mask, texel);
  else blendFloat(format, state, constant, source, mask, texel);
}

NvidiaBlendPlan planNvidiaBlend(const Format& format, const BlendState& state, const glm::vec4& constant, unsigned mask,
                                bool allowFastPath) {
  NvidiaBlendPlan p;
  p.format = format, p.state = state, p.constant = constant, p.mask = mask;
  p.blend = oracle;
  if (!allowFastPath) return p;
  const int c = format.channels;
  if (format.isUnorm()) {
    if (format.isPacked()) return p;
    p.blend = format.unormBits(0) == 8 ? unormOf<8> : format.unormBits(0) == 16 ? unormOf<16> : unormOf<0>;
    return p;
  }
  const ChannelEncoding e = format.encoding();
  const bool fp32 = e == ChannelEncoding::Float32;
  if ((!fp32 && e != ChannelEncoding::Half) || (c != 1 && c != 2 && c != 4) || mask != (1u << c) - 1) return p;
  p.halfRounding = nvidiaProfile().fp16;
  for (int k = 0; k < 4; ++k) {
    p.convertedConstant[k] = fp32 ? daz(constant[k]) : toHalfTowardZero(constant[k]);
    if (!std::isfinite(p.convertedConstant[k])) return p;  // leavesDestination asks for it
  }
  p.lanes.source[0] = state.srcRgb, p.lanes.source[1] = state.srcAlpha;
  p.lanes.destination[0] = state.dstRgb, p.lanes.destination[1] = state.dstAlpha;
  for (int k = 0; k < c; ++k) {
    const bool alpha = k == 3;
    const BlendEquation eq = alpha ? state.equationAlpha : state.equationRgb;
    const BlendFactor sf = alpha ? state.srcAlpha : state.srcRgb, df = alpha ? state.dstAlpha : state.dstRgb;
    if (!isMinMax(eq) && sf == BlendFactor::Zero && df == BlendFactor::Zero) return p;  // a zero sum
    p.lanes.foldSource[k] = -int32_t(sf == BlendFactor::Zero);
    p.lanes.foldDestination[k] = -int32_t(df == BlendFactor::Zero);
    p.lanes.minMax[k] = -int32_t(isMinMax(eq));
    p.lanes.isMin[k] = -int32_t(eq == BlendEquation::Min);
    p.lanes.signSource[k] = eq == BlendEquation::ReverseSubtract ? -1.0 : 1.0;
    p.lanes.signDestination[k] = eq == BlendEquation::Subtract ? -1.0 : 1.0;
    p.lanes.addLike[k] = -int32_t(eq == BlendEquation::Add || eq == BlendEquation::ReverseSubtract);
    p.lanes.destinationOne[k] = -int32_t(df == BlendFactor::One);
    p.lanes.oneIfSourceZero[k] = -int32_t(df == BlendFactor::OneMinusSrcColor);
  }
  p.blend = nvidiaUsualFloatKernel(fp32, c);
  return p;
}

}  // namespace oitref::detail
