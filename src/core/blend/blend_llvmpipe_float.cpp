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
#include "blend/float_texels.h"
#include "blend/method_blend_states.h"

namespace oitref::detail {
namespace {

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
[[gnu::target("fma")]] v4f fusedMultiplyAdd4Hardware(v4f x, v4f y, v4f z) {
  return (v4f)_mm_fmadd_ps((__m128)x, (__m128)y, (__m128)z);
}
[[gnu::target("fma,avx")]] v8f fusedMultiplyAdd8Hardware(v8f x, v8f y, v8f z) {
  return (v8f)_mm256_fmadd_ps((__m256)x, (__m256)y, (__m256)z);
}
bool hardwareFma() {
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

// One pixel: its four channels in four lanes.
LP_INLINE v4f runPixel(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  const Inputs<v4f> in{Vec<v4f>::of(source), Vec<v4f>::of(destination), Vec<v4f>::of(constant),
                       splat(source[3]), splat(destination[3]), splat(constant[3]), v4i{0, 0, 0, -1},
                       plan.shape.hasAlpha};
  return run(plan, in);
}
// Eight lanes: the channels of 8 / channels pixels side by side, with each lane's pixel's
// source, destination and constant alpha beside them.
struct Lanes8 {
  v8f source, destination, constant, sourceAlpha, destinationAlpha, constantAlpha;
};
// `special`: as Arith's deferred (the caller blends the lanes again with it null where it is set);
// `hardwareFlush`: as Arith's hardware.
LP_INLINE v8f runLanes(const LlvmpipeFloatPlan& plan, const Lanes8& l, IntLanesOf<v8f>* special,
                       bool hardwareFlush = false) {
  const Inputs<v8f> in{Vec<v8f>::of(l.source), Vec<v8f>::of(l.destination), Vec<v8f>::of(l.constant),
                       l.sourceAlpha, l.destinationAlpha, l.constantAlpha, v8i{0, 0, 0, -1, 0, 0, 0, -1},
                       plan.shape.hasAlpha};
  return run(plan, in, special, hardwareFlush);
}

v4f general(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  return runPixel(plan, constant, source, destination);
}
// Eight lanes need AVX2's 256-bit integer operations (the DAZ, NaN and tiny tests); without it
// the compiler splits them into scalar code slower than four lanes twice. Chosen at run time
// (llvmpipeFloatTexelsFor); the same IEEE operations per lane as the four-lane path.
#define LP_AVX2 [[gnu::target("avx2")]]

// Pixels [0, n) blended again with every rare lane's rule applied, from the destinations' lanes
// as they were loaded: blendTexels's rare chunk. One function per layout with the shape read at run time
// (the same operations as a shape compiled in, which only folds them), so that each compiled
// function does not carry a second copy of the blend with the rules' scalar loops (most of this
// file's compile time). The plan and the constant's lanes come by value: by reference their
// addresses escaped, and the caller read its compiled shape back from memory after each call
// instead of folding it (twice as slow).
// A group's blend with the shape read at run time, out of line, for the general kernels and the
// rare chunks (blendAgainWithRules): inlined into each, the run-time shape's every branch took 55 s
// of this file's 86 s compile; the same operations per lane, so the same bits.
[[gnu::noinline]] LP_AVX2 v8f runLanesOutOfLine(const LlvmpipeFloatPlan& plan, const Lanes8& l, IntLanesOf<v8f>* special,
                                                 bool hardwareFlush = false) {
  return runLanes(plan, l, special, hardwareFlush);
}

template <typename Pixels>
[[gnu::noinline]] LP_AVX2 void blendAgainWithRules(LlvmpipeFloatPlan plan, v8f constant, v8f constantAlpha,
                                                   Pixels pixels, const v8f* loaded, int n, Rounding fp16) {
  Lanes8 lanes;
  lanes.constant = constant;
  lanes.constantAlpha = constantAlpha;
  for (int i = 0, g = 0; i < n; i += Pixels::P, g += 2) {
    pixels.loadSources(i, lanes.source, lanes.sourceAlpha);
    lanes.destination = loaded[g], lanes.destinationAlpha = loaded[g + 1];
    pixels.store(i, runLanesOutOfLine(plan, lanes, nullptr), fp16);
  }
}

#if defined(__x86_64__)
// llvmpipe's own floating-point mode for the guard's life: DAZ (bit 6) and FTZ (bit 15) set in
// the MXCSR, as Mesa sets them for its rasterizer threads (util_fpstate_set_denorms_to_zero);
// the caller's mode back after.
class FlushInHardware {
 public:
  // `caller`: the MXCSR now (LlvmpipeFloatPlan::callerMxcsr), or 0 to read it.
  explicit FlushInHardware(unsigned caller) : saved_(caller ? caller : _mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }
  ~FlushInHardware() { _mm_setcsr(saved_); }
  FlushInHardware(const FlushInHardware&) = delete;
  FlushInHardware& operator=(const FlushInHardware&) = delete;

 private:
  unsigned saved_;
};
#endif
// Whether a plan's denormal flushes can be left to the MXCSR (x86, and the fused multiply-adds in
// hardware too: std::fma in software does not follow the MXCSR).
bool flushesInHardware(const LlvmpipeFloatPlan& plan) {
#if defined(__x86_64__)
  return plan.flushDenormals && (!plan.fma || hardwareFma());
#else
  (void)plan;
  return false;
#endif
}

// `run` with the shape a compile-time constant; only the denormal mode and fma stay variables.
template <LlvmpipeFloatShape Shape>
LP_INLINE LlvmpipeFloatPlan withShape(const LlvmpipeFloatPlan& plan) {
  LlvmpipeFloatPlan p;
  // Field by field: copied as one object from the template parameter, GCC read the fields back
  // from memory in the kernel instead of folding them.
  p.shape.rs = Shape.rs, p.shape.rd = Shape.rd, p.shape.as = Shape.as, p.shape.ad = Shape.ad;
  p.shape.eqRgb = Shape.eqRgb, p.shape.eqAlpha = Shape.eqAlpha;
  p.shape.channels = Shape.channels, p.shape.hasAlpha = Shape.hasAlpha, p.shape.independent = Shape.independent;
  p.flushDenormals = plan.flushDenormals;
  p.fma = plan.fma;
  return p;
}
// How a kernel knows the shape: compiled in (KnownShape: its folds made when it is compiled, runLanes
// inlined) or read from the plan at run time (ShapeFromPlan: runLanesOutOfLine).
template <LlvmpipeFloatShape Shape>
struct KnownShape {
  static constexpr bool kKnown = true;
  LP_INLINE static LlvmpipeFloatPlan of(const LlvmpipeFloatPlan& plan) { return withShape<Shape>(plan); }
};
struct ShapeFromPlan {
  static constexpr bool kKnown = false;
  LP_INLINE static LlvmpipeFloatPlan of(const LlvmpipeFloatPlan& plan) { return plan; }
};

// Pixels [begin, end) (whole groups) blended with the rare lanes deferred into `special`, their
// destinations' lanes kept in `loaded`. Out of line, so that where the MXCSR flushes
// (HardwareFlush) the call keeps the arithmetic between the guard's two writes of the MXCSR.
template <int Channels, typename ShapeOf, bool HardwareFlush, typename Pixels>
[[gnu::noinline]] LP_AVX2 void blendChunk(const LlvmpipeFloatPlan& planGiven, const Lanes8& constants,
                                          const Pixels& pixels, int begin, int end, v8f* loaded,
                                          IntLanesOf<v8f>* special, Rounding fp16) {
  constexpr int P = 8 / Channels;
  const LlvmpipeFloatPlan plan = ShapeOf::of(planGiven);
  Lanes8 lanes = constants;
  IntLanesOf<v8f> rare{};  // in a register: through the pointer, every operation read and wrote memory
  for (int i = begin, g = 0; i < end; i += P, g += 2) {
    pixels.loadDestinations(i, lanes.destination, lanes.destinationAlpha);
    loaded[g] = lanes.destination, loaded[g + 1] = lanes.destinationAlpha;
    pixels.loadSources(i, lanes.source, lanes.sourceAlpha);
    if constexpr (ShapeOf::kKnown) pixels.store(i, runLanes(plan, lanes, &rare, HardwareFlush), fp16);
    else pixels.store(i, runLanesOutOfLine(plan, lanes, &rare, HardwareFlush), fp16);
  }
  *special = rare;
}

// LlvmpipeFloatTexelsFn's and LlvmpipeFloatRunFn's loop, inlined into each compiled function. Up
// to kChunk pixels are blended with the rare lanes' rules deferred (Arith: one test for the chunk
// instead of one per operation and group); in the rare chunk that has such a lane, every pixel of
// it is blended again from the destinations as they were loaded, with the rules applied. The
// same bits either way. Where the profile flushes denormals, the chunk runs in llvmpipe's own
// MXCSR mode (FlushInHardware) where it can: the flushes cost nothing then, and only NaN lanes are
// rare (their payloads follow x86Nan's rule, which does not depend on the compiler's operand order).
template <int Channels, bool Half, typename ShapeOf, typename Pixels>
LP_INLINE int blendTexels(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const Pixels& pixels, int n,
                          Rounding fp16) {
  constexpr int P = 8 / Channels, kChunk = 64;
  Lanes8 lanes;
  const v4f c = load4(constant);
  v4f cs[P];
  for (v4f& x : cs) x = c;
  gatherLanes<Channels>(cs, lanes.constant, lanes.constantAlpha);
  const int whole = n - n % P;
  const bool hardware = flushesInHardware(plan);
  // A kernel compiled for its shape has one chunk function, built for the MXCSR's flushes: it
  // runs in that mode, or for a plan that does not flush (then `hardware` changes nothing in
  // Arith). The software rule (a CPU without the fused multiply-add in hardware, or not x86)
  // takes the general chunk function: a second compiled copy of every shape doubled this file's
  // build time.
  if constexpr (ShapeOf::kKnown)
    if (plan.flushDenormals && !hardware) return blendTexels<Channels, Half, ShapeFromPlan>(plan, constant, pixels, n, fp16);
  for (int chunk = 0; chunk < whole; chunk += kChunk) {
    const int end = chunk + kChunk < whole ? chunk + kChunk : whole;
    v8f loaded[2 * kChunk / P];  // each group's destination lanes and their alphas
    IntLanesOf<v8f> special{};
    bool done = false;
#if defined(__x86_64__)
    if (hardware) {
      const FlushInHardware mode(plan.callerMxcsr);
      blendChunk<Channels, ShapeOf, true>(plan, lanes, pixels, chunk, end, loaded, &special, fp16);
      done = true;
    }
#endif
    if (!done) blendChunk<Channels, ShapeOf, ShapeOf::kKnown>(plan, lanes, pixels, chunk, end, loaded, &special, fp16);
    if (Arith<v8f>::any(special)) {
      blendAgainWithRules(ShapeOf::of(plan), lanes.constant, lanes.constantAlpha, pixels.from(chunk), loaded,
                          end - chunk, fp16);
    }
  }
  (void)hardware;
  return whole;
}
template <int Channels, bool Half>
LP_AVX2 int generalTexels(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* const* sources,
                          uint8_t* const* texels, int n, Rounding fp16) {
  return blendTexels<Channels, Half, ShapeFromPlan>(plan, constant, ScatteredTexelLanes<Channels, Half>{sources, texels}, n, fp16);
}
template <int Channels, bool Half>
LP_AVX2 int generalRun(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* sources,
                       uint8_t* texels, int n, Rounding fp16) {
  return blendTexels<Channels, Half, ShapeFromPlan>(plan, constant, RunTexelLanes<Channels, Half>{sources, texels}, n, fp16);
}

template <LlvmpipeFloatShape Shape>
v4f compiled(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  return runPixel(withShape<Shape>(plan), constant, source, destination);
}
template <LlvmpipeFloatShape Shape, bool Half>
LP_AVX2 int compiledTexels(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* const* sources,
                           uint8_t* const* texels, int n, Rounding fp16) {
  return blendTexels<Shape.channels, Half, KnownShape<Shape>>(plan, constant,
                                           ScatteredTexelLanes<Shape.channels, Half>{sources, texels}, n, fp16);
}
template <LlvmpipeFloatShape Shape, bool Half>
LP_AVX2 int compiledRun(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* sources,
                        uint8_t* texels, int n, Rounding fp16) {
  return blendTexels<Shape.channels, Half, KnownShape<Shape>>(plan, constant, RunTexelLanes<Shape.channels, Half>{sources, texels},
                                           n, fp16);
}

// One compiled function per method blend state and the float layouts it is drawn into (r, rg: no
// alpha; rgba), as kMethodFloatLayouts lists them.
struct CompiledEntry {
  LlvmpipeFloatShape shape;
  LlvmpipeFloatBlendFn fn;
  LlvmpipeFloatTexelFns texels[2];  // fp32, fp16
};
struct StateLayout {
  size_t state = 0;
  int channels = 0;
};
constexpr size_t kStateLayoutCount = [] {
  size_t n = 0;
  for (unsigned layouts : states::kMethodFloatLayouts) n += size_t(std::popcount(layouts));
  return n;
}();
constexpr auto kStateLayouts = [] {
  std::array<StateLayout, kStateLayoutCount> pairs{};
  size_t n = 0;
  for (size_t i = 0; i < std::size(states::kMethodFloatLayouts); ++i)
    for (int channels : {1, 2, 4})
      if (states::kMethodFloatLayouts[i] & unsigned(channels)) pairs[n++] = {i, channels};
  return pairs;
}();
template <StateLayout P>
constexpr CompiledEntry entry() {
  constexpr LlvmpipeFloatShape shape = llvmpipeFloatShape(P.channels, P.channels == 4, states::kMethodBlendStates[P.state]);
  return {shape,
          &compiled<shape>,
          {{&compiledTexels<shape, false>, &compiledRun<shape, false>}, {&compiledTexels<shape, true>, &compiledRun<shape, true>}}};
}
template <size_t... J>
constexpr auto compiledTable(std::index_sequence<J...>) {
  return std::array<CompiledEntry, sizeof...(J)>{entry<kStateLayouts[J]>()...};
}
constexpr auto kCompiled = compiledTable(std::make_index_sequence<kStateLayoutCount>());

}  // namespace

uint32_t floatModeOfThisThread() {
#if defined(__x86_64__)
  return _mm_getcsr();
#else
  return 0;
#endif
}

LlvmpipeFloatBlendFn llvmpipeFloatBlendFor(const LlvmpipeFloatShape& shape, bool specialised) {
  if (specialised)
    for (const CompiledEntry& e : kCompiled)
      if (e.shape == shape) return e.fn;
  return general;
}

LlvmpipeFloatTexelFns llvmpipeFloatTexelsFor(const LlvmpipeFloatShape& shape, bool half, bool specialised) {
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (!avx2) return {};
#endif
  if (specialised)
    for (const CompiledEntry& e : kCompiled)
      if (e.shape == shape) return e.texels[half];
  constexpr LlvmpipeFloatTexelFns general[3][2] = {
      {{generalTexels<1, false>, generalRun<1, false>}, {generalTexels<1, true>, generalRun<1, true>}},
      {{generalTexels<2, false>, generalRun<2, false>}, {generalTexels<2, true>, generalRun<2, true>}},
      {{generalTexels<4, false>, generalRun<4, false>}, {generalTexels<4, true>, generalRun<4, true>}}};
  return general[shape.channels == 4 ? 2 : shape.channels - 1][half];
}

glm::vec4 blendLlvmpipeFloat(const Format& format, const BlendState& state, const glm::vec4& constant, bool fma,
                             bool flushDenormals, const glm::vec4& source, const glm::vec4& destination) {
  LlvmpipeFloatPlan plan;
  plan.shape = llvmpipeFloatShape(format.channels, format.hasAlpha(), state);
  plan.flushDenormals = flushDenormals;
  plan.fma = fma;
  return store4(runPixel(plan, load4(constant), load4(source), load4(destination)));
}

}  // namespace oitref::detail
