#include "blend/blend_llvmpipe_float.h"

#include <cmath>

#include "blend/llvmpipe_factors.h"

namespace oitref::detail {
namespace {

// A vector of four lanes that may be known, at JIT time, to be all 0 or all 1.
struct Vec {
  enum Kind { Value, Zero, One } kind = Value;
  glm::vec4 v{0.0f};
  static Vec zero() { return {Zero, glm::vec4(0.0f)}; }
  static Vec one() { return {One, glm::vec4(1.0f)}; }
  static Vec of(const glm::vec4& x) { return {Value, x}; }
};

// llvmpipe's generated code runs with the x86 MXCSR's DAZ and FTZ bits set (unless a small-float
// target is bound): a denormal operand reads as a zero of its sign, and a result that is tiny
// after rounding (x86 detects tininess after rounding) is written as a zero of its sign.
// Operations folded away at JIT time (x·1, x + 0, ...) execute nothing, so denormals pass
// through them unchanged. One Arith evaluates the lp_build_* helpers with their constant folds.
class Arith {
 public:
  Arith(bool flush, bool fma) : flush_(flush), fma_(fma) {}

  Vec add(const Vec& a, const Vec& b) const {
    if (a.kind == Vec::Zero) return b;
    if (b.kind == Vec::Zero) return a;
    return lanes(a, b, [](float x, float y, float k) { return x * k + y * k; });
  }
  Vec sub(const Vec& a, const Vec& b) const {
    if (b.kind == Vec::Zero) return a;
    return lanes(a, b, [](float x, float y, float k) { return x * k - y * k; });
  }
  Vec mul(const Vec& a, const Vec& b) const {
    if (a.kind == Vec::Zero || b.kind == Vec::Zero) return Vec::zero();
    if (a.kind == Vec::One) return b;
    if (b.kind == Vec::One) return a;
    return lanes(a, b, [](float x, float y, float k) { return (x * k) * y; });
  }
  Vec comp(const Vec& a) const {  // 1 − a
    if (a.kind == Vec::One) return Vec::zero();
    if (a.kind == Vec::Zero) return Vec::one();
    return sub(Vec::of(glm::vec4(1.0f)), a);
  }
  // x86 minps / maxps: a < b ? a : b, on the DAZ-read operands.
  glm::vec4 minps(const glm::vec4& a, const glm::vec4& b) const {
    glm::vec4 r;
    for (int i = 0; i < 4; ++i) r[i] = daz(a[i]) < daz(b[i]) ? daz(a[i]) : daz(b[i]);
    return r;
  }
  glm::vec4 maxps(const glm::vec4& a, const glm::vec4& b) const {
    glm::vec4 r;
    for (int i = 0; i < 4; ++i) r[i] = daz(a[i]) > daz(b[i]) ? daz(a[i]) : daz(b[i]);
    return r;
  }
  // lp_build_mad: llvm.fmuladd, one rounding on CPUs with FMA.
  Vec mad(const Vec& a, const Vec& b, const Vec& c) const {
    if (!fma_) return add(mul(a, b), c);
    Vec r = Vec::of(glm::vec4(0.0f));
    for (int i = 0; i < 4; ++i) {
      const float x = daz(a.v[i]), y = daz(b.v[i]), z = daz(c.v[i]);
      r.v[i] = ftz([&](float k) { return std::fma(x * k, y, z * k); });
    }
    return r;
  }
  Vec lerp(const Vec& x, const Vec& v0, const Vec& v1) const { return mad(x, sub(v1, v0), v0); }

 private:
  float daz(float x) const { return flush_ && std::fpclassify(x) == FP_SUBNORMAL ? std::copysign(0.0f, x) : x; }

  // `op(k)` computes the operation with its operands scaled by k; k = 2^64 lifts a tiny result
  // into the normal range, where fp32 rounding is the unbounded-exponent rounding.
  template <typename Op>
  float ftz(Op op) const {
    const float r = op(1.0f);
    const float a = std::fabs(r);
    if (!flush_ || r == 0.0f || a > 0x1p-126f || std::isnan(r)) return r;
    if (a < 0x1p-126f || std::fabs(op(0x1p64f)) < 0x1p-62f) return std::copysign(0.0f, r);
    return r;  // exactly ±2^-126 and not tiny before the format's denormal rounding
  }

  template <typename Op>
  Vec lanes(const Vec& a, const Vec& b, Op op) const {
    Vec r = Vec::of(glm::vec4(0.0f));
    for (int i = 0; i < 4; ++i) {
      const float x = daz(a.v[i]), y = daz(b.v[i]);
      r.v[i] = ftz([&](float k) { return op(x, y, k); });
    }
    return r;
  }

  bool flush_, fma_;
};

struct Inputs {
  Vec src, dst, constant;
  float srcAlpha, constAlpha;
  bool hasDstAlpha;
};

// lp_build_blend_factor_unswizzled, then the AAAA broadcast of alpha factors, for one lane
// group: `alphaLane` selects the alpha channel's rules (SRC_ALPHA_SATURATE is 1 there).
Vec unswizzled(const Arith& A, unsigned f, bool alphaLane, const Inputs& in) {
  const glm::vec4 sa(in.srcAlpha), ca(in.constAlpha);
  switch (f) {
    case kPipeZero: return Vec::zero();
    case kPipeOne: return Vec::one();
    case kPipeSrcColor: return in.src;
    case kPipeSrcAlpha: return Vec::of(sa);
    case kPipeDstColor: return in.dst;
    case kPipeDstAlpha: return Vec::of(glm::vec4(in.dst.v[3]));
    case kPipeSrcAlphaSaturate:
      if (alphaLane) return Vec::one();
      return Vec::of(A.minps(sa, in.hasDstAlpha ? glm::vec4(1.0f - in.dst.v[3]) : glm::vec4(0.0f)));
    case kPipeConstColor: return in.constant;
    case kPipeConstAlpha: return Vec::of(ca);
    case kPipeInvSrcColor: return A.comp(in.src);
    case kPipeInvSrcAlpha: return A.comp(Vec::of(sa));
    case kPipeInvDstColor: return A.comp(in.dst);
    case kPipeInvDstAlpha: return A.comp(Vec::of(glm::vec4(in.dst.v[3])));
    case kPipeInvConstColor: return A.comp(in.constant);
    case kPipeInvConstAlpha: return A.comp(Vec::of(ca));
    default: return Vec::zero();
  }
}

// RGB lanes from the RGB factor, the alpha lane from the alpha factor; a constant only when both are.
Vec factorVector(const Arith& A, unsigned rgb, unsigned alpha, const Inputs& in) {
  const Vec r = unswizzled(A, rgb, false, in);
  if (!in.hasDstAlpha) return r;
  const Vec a = unswizzled(A, alpha, true, in);
  if (r.kind != Vec::Value && r.kind == a.kind) return r;
  Vec mixed = Vec::of(r.v);
  mixed.v[3] = a.v[3];
  return mixed;
}

Vec blendFunc(const Arith& A, BlendEquation eq, const Vec& a, const Vec& b) {
  switch (eq) {
    case BlendEquation::Add: return A.add(a, b);
    case BlendEquation::Subtract: return A.sub(a, b);
    case BlendEquation::ReverseSubtract: return A.sub(b, a);
    case BlendEquation::Min: return Vec::of(A.minps(a.v, b.v));
    case BlendEquation::Max: return Vec::of(A.maxps(a.v, b.v));
  }
  return a;
}

// lp_build_blend for floating-point vectors.
Vec lpBlend(const Arith& A, BlendEquation eq, unsigned fs, unsigned fd, const Vec& s, const Vec& d, const Vec& sf,
            const Vec& df, bool channelIndependent) {
  if (channelIndependent) {
    if (pipeComplementary(fs, fd)) {
      const bool srcPlain = fs < fd;
      if (eq == BlendEquation::Add) return srcPlain ? A.lerp(sf, d, s) : A.lerp(df, s, d);
      if (eq == BlendEquation::Subtract) {
        const Vec sum = A.add(s, d);
        return srcPlain ? A.sub(A.mul(sum, sf), d) : A.sub(s, A.mul(sum, df));
      }
      if (eq == BlendEquation::ReverseSubtract) {
        const Vec sum = A.add(s, d);
        return srcPlain ? A.sub(d, A.mul(sum, sf)) : A.sub(A.mul(sum, df), s);
      }
    }
    if (fs == fd && (eq == BlendEquation::Add || eq == BlendEquation::Subtract || eq == BlendEquation::ReverseSubtract))
      return A.mul(blendFunc(A, eq, s, d), sf);
  }
  return blendFunc(A, eq, A.mul(s, sf), A.mul(d, df));
}

}  // namespace

glm::vec4 blendLlvmpipeFloat(const Format& format, const BlendState& state, const glm::vec4& constant, bool fma,
                             bool flushDenormals, const glm::vec4& source, const glm::vec4& destination) {
  const Arith A(flushDenormals, fma);
  const bool hasAlpha = format.hasAlpha();
  const int channels = format.channels;
  unsigned rs = pipeFactor(state.srcRgb), rd = pipeFactor(state.dstRgb);
  unsigned as = pipeFactor(state.srcAlpha), ad = pipeFactor(state.dstAlpha);
  // Mesa's state tracker: MIN and MAX ignore the factors, so it sets them to ONE.
  auto isMinMax = [](BlendEquation e) { return e == BlendEquation::Min || e == BlendEquation::Max; };
  if (isMinMax(state.equationRgb)) rs = rd = kPipeOne;
  if (isMinMax(state.equationAlpha)) as = ad = kPipeOne;
  // llvmpipe (lp_state_fs.c): without a destination alpha channel, Ad = 1 is folded into the
  // RGB factors, and the alpha equation and factors are made the RGB ones.
  BlendEquation eqAlpha = state.equationAlpha;
  if (!hasAlpha) {
    for (unsigned* f : {&rs, &rd}) {
      if (*f == kPipeDstAlpha) *f = kPipeOne;
      else if (*f == kPipeInvDstAlpha) *f = kPipeZero;
    }
    as = rs, ad = rd, eqAlpha = state.equationRgb;
  }
  Inputs in{Vec::of(source), Vec::of(destination), Vec::of(constant), source[3], constant[3], hasAlpha};
  const Vec sf = factorVector(A, rs, as, in), df = factorVector(A, rd, ad, in);
  const bool independent = (rs == rd && as == ad) || channels == 1;
  Vec result = lpBlend(A, state.equationRgb, rs, rd, in.src, in.dst, sf, df, independent);
  if (state.equationRgb != eqAlpha && channels > 1 && hasAlpha)
    result.v[3] = lpBlend(A, eqAlpha, as, ad, in.src, in.dst, sf, df, independent).v[3];
  return result.v;
}

}  // namespace oitref::detail
