// llvmpipe's floating-point blend arithmetic (lp_build_blend, lp_bld_blend*.c, and the
// lp_build_* helpers of lp_bld_arit.c it calls) over vector lanes, with the constant folds
// llvmpipe's JIT makes and the x86 DAZ/FTZ mode its code runs in: what a blend computes, lane by
// lane. blend_llvmpipe_float.cpp runs it over texels (one pixel, or eight lanes of pixels) and
// compiles it per method blend state; only that file includes this one.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "blend/blend_llvmpipe_float.h"
#include "blend/blend_math.h"
#include "blend/llvmpipe_factors.h"

namespace oitref::detail::llvmpipe_float {

// Every helper is inlined into each compiled blend function, so that a state known when it is
// compiled folds away (as llvmpipe's JIT folds it).
#define LP_INLINE [[gnu::always_inline]] inline

// Lanes: four (one pixel's channels, as `run` is called per fragment) or eight (Lanes8:
// the channels of two to eight pixels side by side, the batch path). Every operation below is
// per lane, and what depends on a pixel (its source and destination alpha) arrives as lanes, so
// the bits of a lane do not depend on how many lanes travel together. (v8f, IntLanesOf, select,
// splatLanes: blend_math.h.)
template <typename V>
constexpr int kLanes = int(sizeof(V) / sizeof(float));

// A vector of lanes that may be known, at JIT time, to be all 0 or all 1.
// The lanes live in a vector register: built and read in memory, a 16-byte load after narrower
// stores would wait for them (store forwarding).
template <typename V>
struct Vec {
  enum Kind { Value, Zero, One } kind = Value;
  V v{};
  static Vec zero() { return {Zero, splatLanes<V>(0.0f)}; }
  static Vec one() { return {One, splatLanes<V>(1.0f)}; }
  static Vec of(V x) { return {Value, x}; }
};

// x·y + z rounded once, per lane (IEEE fusedMultiplyAdd): the CPU's FMA instruction where it has
// one (chosen at run time; the build does not assume FMA), else std::fma. The same bits either
// way; NaN results are then replaced by the stated rule (x86Nan), so their payloads do not depend
// on the path either.
#if defined(__x86_64__)
[[gnu::target("fma")]] inline v4f fusedMultiplyAdd4Hardware(v4f x, v4f y, v4f z) {
  return (v4f)_mm_fmadd_ps((__m128)x, (__m128)y, (__m128)z);
}
[[gnu::target("fma,avx")]] inline v8f fusedMultiplyAdd8Hardware(v8f x, v8f y, v8f z) {
  return (v8f)_mm256_fmadd_ps((__m256)x, (__m256)y, (__m256)z);
}
inline bool hardwareFma() {
  static const bool supported = __builtin_cpu_supports("fma");
  return supported;
}
#endif
template <typename V>
LP_INLINE V fusedMultiplyAdd(V x, V y, V z) {
#if defined(__x86_64__)
  if (hardwareFma()) {
    if constexpr (kLanes<V> == 4) return fusedMultiplyAdd4Hardware(x, y, z);
    else return fusedMultiplyAdd8Hardware(x, y, z);
  }
#endif
  V r;
  for (int i = 0; i < kLanes<V>; ++i) r[i] = std::fma(x[i], y[i], z[i]);
  return r;
}

// llvmpipe's generated code runs with the x86 MXCSR's DAZ and FTZ bits set (unless a small-float
// target is bound): a denormal operand reads as a zero of its sign, and a result that is tiny
// after rounding (x86 detects tininess after rounding) is written as a zero of its sign.
// Operations folded away at JIT time (x·1, x + 0, ...) execute nothing, so denormals pass
// through them unchanged. One Arith evaluates the lp_build_* helpers with their constant folds.
template <typename V>
class Arith {
 public:
  using VecT = Vec<V>;
  using VI = IntLanesOf<V>;
  static constexpr int N = kLanes<V>;
  // `deferred`: where not null, an operation does not fix its rare lanes (NaN, tiny) itself but
  // marks them there, and the caller runs the whole blend again without it when any is marked
  // (blendTexels): one test per chunk of pixels instead of one per operation, the same bits.
  // `hardware`: the caller has set DAZ and FTZ in the MXCSR (FlushInHardware), as llvmpipe's
  // threads run: the arithmetic flushes by itself, and only NaN lanes are rare. minps and maxps
  // still read their operands through daz: compiled as a compare and a select, they return an
  // operand as it is, not as DAZ read it.
  Arith(bool flush, bool fma, VI* deferred = nullptr, bool hardware = false)
      : flush_(flush), fma_(fma), hardware_(flush && hardware), deferred_(deferred) {}

  LP_INLINE VecT add(const VecT& a, const VecT& b) const {
    if (a.kind == VecT::Zero) return b;
    if (b.kind == VecT::Zero) return a;
    return lanes(a, b, [](auto x, auto y, auto k) { return x * k + y * k; });
  }
  LP_INLINE VecT sub(const VecT& a, const VecT& b) const {
    if (b.kind == VecT::Zero) return a;
    return lanes(a, b, [](auto x, auto y, auto k) { return x * k - y * k; });
  }
  LP_INLINE VecT mul(const VecT& a, const VecT& b) const {
    if (a.kind == VecT::Zero || b.kind == VecT::Zero) return VecT::zero();
    if (a.kind == VecT::One) return b;
    if (b.kind == VecT::One) return a;
    return lanes(a, b, [](auto x, auto y, auto k) { return (x * k) * y; });
  }
  LP_INLINE VecT comp(const VecT& a) const {  // 1 − a
    if (a.kind == VecT::One) return VecT::zero();
    if (a.kind == VecT::Zero) return VecT::one();
    return sub(VecT::of(splatLanes<V>(1.0f)), a);
  }
  // x86 minps / maxps: a < b ? a : b (else b, NaN included), on the DAZ-read operands.
  LP_INLINE V minps(V a, V b) const {
    const V x = daz(a), y = daz(b);
    return select(x < y, x, y);
  }
  LP_INLINE V maxps(V a, V b) const {
    const V x = daz(a), y = daz(b);
    return select(x > y, x, y);
  }
  // lp_build_mad: llvm.fmuladd, one rounding on CPUs with FMA.
  LP_INLINE VecT mad(const VecT& a, const VecT& b, const VecT& c) const {
    if (!fma_) return add(mul(a, b), c);
    const V x = arithmeticDaz(a.v), y = arithmeticDaz(b.v), z = arithmeticDaz(c.v);
    V r = fusedMultiplyAdd(x, y, z);
    // Lanes that are NaN or may be tiny (rare) take the scalar rules; the test is on the vector.
    const VI magnitude = (VI)r & 0x7fffffff;
    const VI special = (magnitude > 0x7f800000) | (softwareFlush() ? (magnitude <= 0x00800000) & (magnitude != 0) : VI{});
    if (deferred_) {
      *deferred_ |= special;
      return VecT::of(r);
    }
    if (any(special))
      for (int i = 0; i < N; ++i) {
        if (r[i] != r[i]) r[i] = x86Nan(x[i], y[i], x86Nan(z[i], z[i], std::bit_cast<float>(0xffc00000u)));
        const float m = std::fabs(r[i]);
        if (flush_ && m != 0.0f && m <= 0x1p-126f)  // may be tiny: the scalar rule
          r[i] = ftz([&](float k) { return std::fma(x[i] * k, y[i], z[i] * k); });
      }
    return VecT::of(r);
  }
  LP_INLINE VecT lerp(const VecT& x, const VecT& v0, const VecT& v1) const { return mad(x, sub(v1, v0), v0); }

  // Whether any lane is set, with one vector test: or-ing the lanes one by one moved each into a
  // general register first, and these tests run several times in every blend call.
  LP_INLINE static bool any(VI m) {
#if defined(__x86_64__)
    if constexpr (N == 8) {  // the halves or-ed, then SSE2's byte mask (no AVX intrinsic: this
                             // body is also compiled where AVX is not the default)
      const auto half = __builtin_shufflevector(m, m, 0, 1, 2, 3) | __builtin_shufflevector(m, m, 4, 5, 6, 7);
      return _mm_movemask_epi8((__m128i)half) != 0;
    } else {
      return _mm_movemask_epi8((__m128i)m) != 0;
    }
#else
    int any = 0;
    for (int i = 0; i < N; ++i) any |= m[i];
    return any != 0;
#endif
  }

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

  // All lanes at once; only lanes whose result may be tiny (|r| ≤ 2^-126, rare) take the
  // scalar rule above, so the bits are those of ftz per lane.
  template <typename Op>
  LP_INLINE VecT lanes(const VecT& a, const VecT& b, Op op) const {
    const V x = arithmeticDaz(a.v), y = arithmeticDaz(b.v);
    V r = op(x, y, splatLanes<V>(1.0f));
    // Lanes that are NaN or may be tiny (rare) take the scalar rules; the test is on the vector.
    const VI magnitude = (VI)r & 0x7fffffff;
    const VI nan = magnitude > 0x7f800000;
    const VI tiny = softwareFlush() ? (magnitude <= 0x00800000) & (magnitude != 0) : VI{};
    if (deferred_) {
      *deferred_ |= nan | tiny;
      return VecT::of(r);
    }
    if (any(nan | tiny))
      for (int i = 0; i < N; ++i) {
        if (nan[i]) r[i] = x86Nan(x[i], y[i], r[i]);
        if (tiny[i]) r[i] = ftz([&](float k) { return op(x[i], y[i], k); });
      }
    return VecT::of(r);
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
  // daz on every lane: a denormal (exponent bits 0) keeps only its sign.
  LP_INLINE V daz(V v) const {
    if (!flush_) return v;
    const VI bits = (VI)v;
    return (V)(((bits & 0x7f800000) == 0) ? (bits & int32_t(0x80000000u)) : bits);
  }
  // The operands of add, sub, mul and mad: flushed here unless the MXCSR does it.
  LP_INLINE V arithmeticDaz(V v) const { return hardware_ ? v : daz(v); }
  LP_INLINE bool softwareFlush() const { return flush_ && !hardware_; }

  bool flush_, fma_, hardware_;
  VI* deferred_;
};

// What a blend reads, lane by lane: srcAlpha, dstAlpha and constAlpha hold each lane's pixel's
// alpha (the broadcasts of llvmpipe's AAAA swizzles); `alphaLanes` marks the lanes that are an
// RGBA pixel's alpha channel.
template <typename V>
struct Inputs {
  Vec<V> src, dst, constant;
  V srcAlpha, dstAlpha, constAlpha;
  IntLanesOf<V> alphaLanes;
  bool hasDstAlpha;
};

// lp_build_blend_factor_unswizzled, then the AAAA broadcast of alpha factors, for one lane
// group: `alphaLane` selects the alpha channel's rules (SRC_ALPHA_SATURATE is 1 there).
template <typename V>
LP_INLINE Vec<V> unswizzled(const Arith<V>& A, unsigned f, bool alphaLane, const Inputs<V>& in) {
  using VecT = Vec<V>;
  switch (f) {
    case kPipeZero: return VecT::zero();
    case kPipeOne: return VecT::one();
    case kPipeSrcColor: return in.src;
    case kPipeSrcAlpha: return VecT::of(in.srcAlpha);
    case kPipeDstColor: return in.dst;
    case kPipeDstAlpha: return VecT::of(in.dstAlpha);
    case kPipeSrcAlphaSaturate:
      if (alphaLane) return VecT::one();
      return VecT::of(A.minps(in.srcAlpha, in.hasDstAlpha ? splatLanes<V>(1.0f) - in.dstAlpha : splatLanes<V>(0.0f)));
    case kPipeConstColor: return in.constant;
    case kPipeConstAlpha: return VecT::of(in.constAlpha);
    case kPipeInvSrcColor: return A.comp(in.src);
    case kPipeInvSrcAlpha: return A.comp(VecT::of(in.srcAlpha));
    case kPipeInvDstColor: return A.comp(in.dst);
    case kPipeInvDstAlpha: return A.comp(VecT::of(in.dstAlpha));
    case kPipeInvConstColor: return A.comp(in.constant);
    case kPipeInvConstAlpha: return A.comp(VecT::of(in.constAlpha));
    default: return VecT::zero();
  }
}

// RGB lanes from the RGB factor, the alpha lane from the alpha factor; a constant only when both are.
template <typename V>
LP_INLINE Vec<V> factorVector(const Arith<V>& A, unsigned rgb, unsigned alpha, const Inputs<V>& in) {
  const Vec<V> r = unswizzled(A, rgb, false, in);
  if (!in.hasDstAlpha) return r;
  const Vec<V> a = unswizzled(A, alpha, true, in);
  if (r.kind != Vec<V>::Value && r.kind == a.kind) return r;
  return Vec<V>::of(select(in.alphaLanes, a.v, r.v));
}

template <typename V>
LP_INLINE Vec<V> blendFunc(const Arith<V>& A, BlendEquation eq, const Vec<V>& a, const Vec<V>& b) {
  switch (eq) {
    case BlendEquation::Add: return A.add(a, b);
    case BlendEquation::Subtract: return A.sub(a, b);
    case BlendEquation::ReverseSubtract: return A.sub(b, a);
    case BlendEquation::Min: return Vec<V>::of(A.minps(a.v, b.v));
    case BlendEquation::Max: return Vec<V>::of(A.maxps(a.v, b.v));
  }
  return a;
}

// lp_build_blend for floating-point vectors.
template <typename V>
LP_INLINE Vec<V> lpBlend(const Arith<V>& A, BlendEquation eq, unsigned fs, unsigned fd, const Vec<V>& s,
                         const Vec<V>& d, const Vec<V>& sf, const Vec<V>& df, bool channelIndependent) {
  if (channelIndependent) {
    if (pipeComplementary(fs, fd)) {
      const bool srcPlain = fs < fd;
      if (eq == BlendEquation::Add) return srcPlain ? A.lerp(sf, d, s) : A.lerp(df, s, d);
      if (eq == BlendEquation::Subtract) {
        const Vec<V> sum = A.add(s, d);
        return srcPlain ? A.sub(A.mul(sum, sf), d) : A.sub(s, A.mul(sum, df));
      }
      if (eq == BlendEquation::ReverseSubtract) {
        const Vec<V> sum = A.add(s, d);
        return srcPlain ? A.sub(d, A.mul(sum, sf)) : A.sub(A.mul(sum, df), s);
      }
    }
    if (fs == fd && (eq == BlendEquation::Add || eq == BlendEquation::Subtract || eq == BlendEquation::ReverseSubtract))
      return A.mul(blendFunc(A, eq, s, d), sf);
  }
  return blendFunc(A, eq, A.mul(s, sf), A.mul(d, df));
}

template <typename V>
LP_INLINE V run(const LlvmpipeFloatPlan& plan, const Inputs<V>& in, IntLanesOf<V>* deferred = nullptr,
                bool hardwareFlush = false) {
  const LlvmpipeFloatShape& p = plan.shape;
  const Arith<V> A(plan.flushDenormals, plan.fma, deferred, hardwareFlush);
  const Vec<V> sf = factorVector(A, p.rs, p.as, in), df = factorVector(A, p.rd, p.ad, in);
  Vec<V> result = lpBlend(A, p.eqRgb, p.rs, p.rd, in.src, in.dst, sf, df, p.independent);
  if (p.eqRgb != p.eqAlpha && p.channels > 1 && p.hasAlpha)
    result.v = select(in.alphaLanes, lpBlend(A, p.eqAlpha, p.as, p.ad, in.src, in.dst, sf, df, p.independent).v,
                              result.v);
  return result.v;
}

}  // namespace oitref::detail::llvmpipe_float
