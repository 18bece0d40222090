#include "blend/blend_llvmpipe_float.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include <utility>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "blend/blend_math.h"
#include "blend/method_blend_states.h"

namespace oitref::detail {
namespace {

// Every helper is inlined into each compiled blend function, so that a state known when it is
// compiled folds away (as llvmpipe's JIT folds it).
#define LP_INLINE [[gnu::always_inline]] inline

// A vector of four lanes that may be known, at JIT time, to be all 0 or all 1.
// The lanes live in a vector register: built and read in memory, a 16-byte load after narrower
// stores would wait for them (store forwarding).
struct Vec {
  enum Kind { Value, Zero, One } kind = Value;
  v4f v{};
  static Vec zero() { return {Zero, splat(0.0f)}; }
  static Vec one() { return {One, splat(1.0f)}; }
  static Vec of(v4f x) { return {Value, x}; }
};

// x·y + z rounded once, per lane (IEEE fusedMultiplyAdd): the CPU's FMA instruction where it has
// one (chosen at run time; the build does not assume FMA), else std::fma. The same bits either
// way; NaN results are then replaced by the stated rule (x86Nan), so their payloads do not depend
// on the path either.
#if defined(__x86_64__)
[[gnu::target("fma")]] v4f fusedMultiplyAdd4Hardware(v4f x, v4f y, v4f z) {
  return (v4f)_mm_fmadd_ps((__m128)x, (__m128)y, (__m128)z);
}
#endif
v4f fusedMultiplyAdd4(v4f x, v4f y, v4f z) {
#if defined(__x86_64__)
  static const bool hardware = __builtin_cpu_supports("fma");
  if (hardware) return fusedMultiplyAdd4Hardware(x, y, z);
#endif
  return v4f{std::fma(x[0], y[0], z[0]), std::fma(x[1], y[1], z[1]), std::fma(x[2], y[2], z[2]), std::fma(x[3], y[3], z[3])};
}

// llvmpipe's generated code runs with the x86 MXCSR's DAZ and FTZ bits set (unless a small-float
// target is bound): a denormal operand reads as a zero of its sign, and a result that is tiny
// after rounding (x86 detects tininess after rounding) is written as a zero of its sign.
// Operations folded away at JIT time (x·1, x + 0, ...) execute nothing, so denormals pass
// through them unchanged. One Arith evaluates the lp_build_* helpers with their constant folds.
class Arith {
 public:
  Arith(bool flush, bool fma) : flush_(flush), fma_(fma) {}

  LP_INLINE Vec add(const Vec& a, const Vec& b) const {
    if (a.kind == Vec::Zero) return b;
    if (b.kind == Vec::Zero) return a;
    return lanes(a, b, [](auto x, auto y, auto k) { return x * k + y * k; });
  }
  LP_INLINE Vec sub(const Vec& a, const Vec& b) const {
    if (b.kind == Vec::Zero) return a;
    return lanes(a, b, [](auto x, auto y, auto k) { return x * k - y * k; });
  }
  LP_INLINE Vec mul(const Vec& a, const Vec& b) const {
    if (a.kind == Vec::Zero || b.kind == Vec::Zero) return Vec::zero();
    if (a.kind == Vec::One) return b;
    if (b.kind == Vec::One) return a;
    return lanes(a, b, [](auto x, auto y, auto k) { return (x * k) * y; });
  }
  LP_INLINE Vec comp(const Vec& a) const {  // 1 − a
    if (a.kind == Vec::One) return Vec::zero();
    if (a.kind == Vec::Zero) return Vec::one();
    return sub(Vec::of(splat(1.0f)), a);
  }
  // x86 minps / maxps: a < b ? a : b (else b, NaN included), on the DAZ-read operands.
  LP_INLINE v4f minps(v4f a, v4f b) const {
    const v4f x = daz4(a), y = daz4(b);
    return select(x < y, x, y);
  }
  LP_INLINE v4f maxps(v4f a, v4f b) const {
    const v4f x = daz4(a), y = daz4(b);
    return select(x > y, x, y);
  }
  // lp_build_mad: llvm.fmuladd, one rounding on CPUs with FMA.
  LP_INLINE Vec mad(const Vec& a, const Vec& b, const Vec& c) const {
    if (!fma_) return add(mul(a, b), c);
    const v4f x = daz4(a.v), y = daz4(b.v), z = daz4(c.v);
    v4f r = fusedMultiplyAdd4(x, y, z);
    // Lanes that are NaN or may be tiny (rare) take the scalar rules; the test is on the vector.
    const v4i magnitude = (v4i)r & 0x7fffffff;
    const v4i special = (magnitude > 0x7f800000) | (flush_ ? (magnitude <= 0x00800000) & (magnitude != 0) : v4i{});
    if (special[0] | special[1] | special[2] | special[3])
      for (int i = 0; i < 4; ++i) {
        if (r[i] != r[i]) r[i] = x86Nan(x[i], y[i], x86Nan(z[i], z[i], std::bit_cast<float>(0xffc00000u)));
        const float m = std::fabs(r[i]);
        if (flush_ && m != 0.0f && m <= 0x1p-126f)  // may be tiny: the scalar rule
          r[i] = ftz([&](float k) { return std::fma(x[i] * k, y[i], z[i] * k); });
      }
    return Vec::of(r);
  }
  LP_INLINE Vec lerp(const Vec& x, const Vec& v0, const Vec& v1) const { return mad(x, sub(v1, v0), v0); }

 private:
  // `op(k)` computes the operation with its operands scaled by k; k = 2^64 lifts a tiny result
  // into the normal range, where fp32 rounding is the unbounded-exponent rounding.
  template <typename Op>
  LP_INLINE float ftz(Op op) const {
    const float r = op(1.0f);
    const float a = std::fabs(r);
    if (!flush_ || r == 0.0f || a > 0x1p-126f || std::isnan(r)) return r;
    if (a < 0x1p-126f || std::fabs(op(0x1p64f)) < 0x1p-62f) return std::copysign(0.0f, r);
    return r;  // exactly ±2^-126 and not tiny before the format's denormal rounding
  }

  // Four lanes at once; only lanes whose result may be tiny (|r| ≤ 2^-126, rare) take the
  // scalar rule above, so the bits are those of ftz per lane.
  template <typename Op>
  LP_INLINE Vec lanes(const Vec& a, const Vec& b, Op op) const {
    const v4f x = daz4(a.v), y = daz4(b.v);
    v4f r = op(x, y, splat(1.0f));
    // Lanes that are NaN or may be tiny (rare) take the scalar rules; the test is on the vector.
    const v4i magnitude = (v4i)r & 0x7fffffff;
    const v4i nan = magnitude > 0x7f800000;
    const v4i tiny = flush_ ? (magnitude <= 0x00800000) & (magnitude != 0) : v4i{};
    const v4i special = nan | tiny;
    if (special[0] | special[1] | special[2] | special[3])
      for (int i = 0; i < 4; ++i) {
        if (nan[i]) r[i] = x86Nan(x[i], y[i], r[i]);
        if (tiny[i]) r[i] = ftz([&](float k) { return op(x[i], y[i], k); });
      }
    return Vec::of(r);
  }
  // x86's NaN propagation, stated so that it does not depend on how the compiler orders the
  // operands of a commutative operation: a NaN result is the first operand's NaN, else the
  // second's, quieted; else the one the operation produced (x86's default NaN).
  static float x86Nan(float x, float y, float r) {
    auto quiet = [](float v) {
      uint32_t b;
      std::memcpy(&b, &v, 4);
      b |= 0x00400000u;
      std::memcpy(&v, &b, 4);
      return v;
    };
    return x != x ? quiet(x) : y != y ? quiet(y) : r;
  }
  // daz on four lanes: a denormal (exponent bits 0) keeps only its sign.
  LP_INLINE v4f daz4(v4f v) const {
    if (!flush_) return v;
    const v4i bits = (v4i)v;
    return (v4f)(((bits & 0x7f800000) == 0) ? (bits & int32_t(0x80000000u)) : bits);
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
LP_INLINE Vec unswizzled(const Arith& A, unsigned f, bool alphaLane, const Inputs& in) {
  const v4f sa = splat(in.srcAlpha), ca = splat(in.constAlpha);
  switch (f) {
    case kPipeZero: return Vec::zero();
    case kPipeOne: return Vec::one();
    case kPipeSrcColor: return in.src;
    case kPipeSrcAlpha: return Vec::of(sa);
    case kPipeDstColor: return in.dst;
    case kPipeDstAlpha: return Vec::of(splat(in.dst.v[3]));
    case kPipeSrcAlphaSaturate:
      if (alphaLane) return Vec::one();
      return Vec::of(A.minps(sa, splat(in.hasDstAlpha ? 1.0f - in.dst.v[3] : 0.0f)));
    case kPipeConstColor: return in.constant;
    case kPipeConstAlpha: return Vec::of(ca);
    case kPipeInvSrcColor: return A.comp(in.src);
    case kPipeInvSrcAlpha: return A.comp(Vec::of(sa));
    case kPipeInvDstColor: return A.comp(in.dst);
    case kPipeInvDstAlpha: return A.comp(Vec::of(splat(in.dst.v[3])));
    case kPipeInvConstColor: return A.comp(in.constant);
    case kPipeInvConstAlpha: return A.comp(Vec::of(ca));
    default: return Vec::zero();
  }
}

// RGB lanes from the RGB factor, the alpha lane from the alpha factor; a constant only when both are.
LP_INLINE Vec factorVector(const Arith& A, unsigned rgb, unsigned alpha, const Inputs& in) {
  const Vec r = unswizzled(A, rgb, false, in);
  if (!in.hasDstAlpha) return r;
  const Vec a = unswizzled(A, alpha, true, in);
  if (r.kind != Vec::Value && r.kind == a.kind) return r;
  Vec mixed = Vec::of(r.v);
  mixed.v[3] = a.v[3];
  return mixed;
}

LP_INLINE Vec blendFunc(const Arith& A, BlendEquation eq, const Vec& a, const Vec& b) {
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
LP_INLINE Vec lpBlend(const Arith& A, BlendEquation eq, unsigned fs, unsigned fd, const Vec& s, const Vec& d, const Vec& sf,
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

LP_INLINE v4f run(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  const LlvmpipeFloatShape& p = plan.shape;
  const Arith A(plan.flushDenormals, plan.fma);
  Inputs in{Vec::of(source), Vec::of(destination), Vec::of(constant), source[3], constant[3], p.hasAlpha};
  const Vec sf = factorVector(A, p.rs, p.as, in), df = factorVector(A, p.rd, p.ad, in);
  Vec result = lpBlend(A, p.eqRgb, p.rs, p.rd, in.src, in.dst, sf, df, p.independent);
  if (p.eqRgb != p.eqAlpha && p.channels > 1 && p.hasAlpha)
    result.v[3] = lpBlend(A, p.eqAlpha, p.as, p.ad, in.src, in.dst, sf, df, p.independent).v[3];
  return result.v;
}

v4f general(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  return run(plan, constant, source, destination);
}

// `run` with the shape a compile-time constant; only the denormal mode and fma stay variables.
template <LlvmpipeFloatShape Shape>
v4f compiled(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  LlvmpipeFloatPlan p;
  p.shape = Shape;
  p.flushDenormals = plan.flushDenormals;
  p.fma = plan.fma;
  return run(p, constant, source, destination);
}

// One compiled function per method blend state and float layout: r, rg (no alpha) and rgba.
struct CompiledEntry {
  LlvmpipeFloatShape shape;
  LlvmpipeFloatBlendFn fn;
};
template <size_t I, int Channels>
constexpr CompiledEntry entry() {
  constexpr LlvmpipeFloatShape shape = llvmpipeFloatShape(Channels, Channels == 4, states::kMethodBlendStates[I]);
  return {shape, &compiled<shape>};
}
template <size_t... I>
constexpr auto compiledTable(std::index_sequence<I...>) {
  return std::array<CompiledEntry, 3 * sizeof...(I)>{entry<I, 1>()..., entry<I, 2>()..., entry<I, 4>()...};
}
constexpr auto kCompiled = compiledTable(std::make_index_sequence<std::size(states::kMethodBlendStates)>());

}  // namespace

LlvmpipeFloatBlendFn llvmpipeFloatBlendFor(const LlvmpipeFloatShape& shape, bool specialised) {
  if (specialised)
    for (const CompiledEntry& e : kCompiled)
      if (e.shape == shape) return e.fn;
  return general;
}

glm::vec4 blendLlvmpipeFloat(const Format& format, const BlendState& state, const glm::vec4& constant, bool fma,
                             bool flushDenormals, const glm::vec4& source, const glm::vec4& destination) {
  LlvmpipeFloatPlan plan;
  plan.shape = llvmpipeFloatShape(format.channels, format.hasAlpha(), state);
  plan.flushDenormals = flushDenormals;
  plan.fma = fma;
  return store4(run(plan, load4(constant), load4(source), load4(destination)));
}

}  // namespace oitref::detail
