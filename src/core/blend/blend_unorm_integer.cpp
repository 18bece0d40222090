#include "blend/blend_unorm_integer.h"

#include <array>
#include <cstring>
#include <utility>

#include "blend/blend_factor.h"
#include "blend/blend_math.h"
#include "blend/llvmpipe_factors.h"
#include "blend/method_blend_states.h"
#include "format/packed_layout.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace oitref::detail {
namespace {

// Inlined into each compiled blend function, so that a state known when it is compiled folds away.
#define UI_INLINE [[gnu::always_inline]] inline

// Channel ch of a factor: candidate row of blend_factor.h in w-bit integers, 1 − v as max − v.
UI_INLINE uint32_t factorInteger(BlendFactor f, int ch, const uint32_t s[4], const uint32_t d[4], uint32_t ad, const uint32_t c[4],
                       uint32_t max) {
  const FactorRow fr = factorRow(f);
  uint32_t v = 0;
  switch (fr.row) {
    case 0: v = 0; break;
    case 1: v = s[ch]; break;
    case 2: v = ch == 3 ? ad : d[ch]; break;
    case 3: v = s[3]; break;
    case 4: v = ad; break;
    case 5: v = c[ch]; break;
    case 6: v = c[3]; break;
    case 7: v = ch == 3 ? max : (s[3] < max - ad ? s[3] : max - ad); break;
  }
  return fr.oneMinus ? max - v : v;
}

UI_INLINE uint32_t equationInteger(BlendEquation eq, uint32_t s, uint32_t d, uint32_t sf, uint32_t df, int w) {
  const int64_t a = mulUnormInteger(s, sf, w), b = mulUnormInteger(d, df, w), max = (int64_t(1) << w) - 1;
  int64_t r = 0;
  switch (eq) {
    case BlendEquation::Add: r = a + b; break;
    case BlendEquation::Subtract: r = a - b; break;
    case BlendEquation::ReverseSubtract: r = b - a; break;
    case BlendEquation::Min: return s < d ? s : d;
    case BlendEquation::Max: return s > d ? s : d;
  }
  return uint32_t(r < 0 ? 0 : r > max ? max : r);  // saturating, as the integer ops are
}

// lp_build_lerp on 8-bit normalized integers (SSSE3 pmulhrsw path): x scaled to [0, 256] as
// x + (x >> 7), then v0 + ((x·(v1 − v0) + 128) >> 8) (arithmetic shift), modulo 256.
UI_INLINE uint32_t lerpUnorm8(uint32_t x, uint32_t v0, uint32_t v1) {
  const int scaled = int(x + (x >> 7));
  const int delta = int(v1) - int(v0);
  const int step = (scaled * delta + 128) >> 8;  // C++20: >> on negatives is arithmetic
  return uint32_t(int(v0) + step) & 0xffu;
}

// The same on 16-bit normalized integers, widened to 32 bits (no pmulhrsw): x scaled to
// [0, 65536] as x + (x >> 15), then v0 + ((x·(v1 − v0)) >> 16), truncating (arithmetic shift).
UI_INLINE uint32_t lerpUnorm16(uint32_t x, uint32_t v0, uint32_t v1) {
  const int64_t scaled = int64_t(x + (x >> 15));
  const int64_t delta = int64_t(v1) - int64_t(v0);
  return uint32_t(int64_t(v0) + ((scaled * delta) >> 16)) & 0xffffu;
}

// llvmpipe blends a one-channel UNORM target with complementary factors and ADD as a lerp
// (lp_build_blend: the factors cannot differ between channels when there is one channel).
// Factors are first sanitised as llvmpipe does for targets without alpha.
bool isLerpCase(const Format& f, const BlendState& st, unsigned& fs, unsigned& fd) {
  if (f.channels != 1 || st.equationRgb != BlendEquation::Add) return false;
  auto sanitise = [](unsigned p) {
    return p == kPipeDstAlpha ? kPipeOne : (p == kPipeInvDstAlpha || p == kPipeSrcAlphaSaturate) ? kPipeZero : p;
  };
  fs = sanitise(pipeFactor(st.srcRgb));
  fd = sanitise(pipeFactor(st.dstRgb));
  return pipeComplementary(fs, fd);
}

// The stored n-bit codes of the texel (missing channels: 0, alpha max).
UI_INLINE void loadCodes(const UnormIntegerPlan& p, const uint8_t* texel, uint32_t codes[4]) {
  if (p.rgb10a2) {
    uint32_t w;
    std::memcpy(&w, texel, 4);
    for (int ch = 0; ch < 4; ++ch) codes[ch] = (w >> kRgb10a2Shift[ch]) & ((1u << kRgb10a2Bits[ch]) - 1);
  } else if (p.bits[0] == 8) {
    for (int ch = 0; ch < p.channels; ++ch) codes[ch] = texel[ch];
  } else {
    for (int ch = 0; ch < p.channels; ++ch) {
      uint16_t v;
      std::memcpy(&v, texel + 2 * ch, 2);  // little-endian, like the texel
      codes[ch] = v;
    }
  }
}

UI_INLINE void storeCodes(const UnormIntegerPlan& p, const uint32_t codes[4], uint8_t* texel) {
  if (p.rgb10a2) {
    uint32_t w;
    std::memcpy(&w, texel, 4);
    for (int ch = 0; ch < 4; ++ch) {
      if (!(p.writeMask & (1u << ch))) continue;
      const uint32_t m = ((1u << kRgb10a2Bits[ch]) - 1) << kRgb10a2Shift[ch];
      w = (w & ~m) | (codes[ch] << kRgb10a2Shift[ch]);
    }
    std::memcpy(texel, &w, 4);
  } else if (p.bits[0] == 8) {
    for (int ch = 0; ch < p.channels; ++ch)
      if (p.writeMask & (1u << ch)) texel[ch] = uint8_t(codes[ch]);
  } else {
    for (int ch = 0; ch < p.channels; ++ch)
      if (p.writeMask & (1u << ch)) {
        const uint16_t v = uint16_t(codes[ch]);
        std::memcpy(texel + 2 * ch, &v, 2);
      }
  }
}

UI_INLINE void run(const UnormIntegerPlan& p, const glm::vec4& source, uint8_t* texel) {
  const int w = p.w;
  const uint32_t max = p.max;
  const BlendState& state = p.state;
  uint32_t s[4], d[4] = {0, 0, 0, max}, codes[4] = {0, 0, 0, 0};
  if (p.rounding != UnormRounding::NvidiaFixed || w <= 12) {  // encodeUnorm4's range: the same bits, four at once
    const v4i codes4 = encodeUnorm4(load4(source), w, p.rounding);
    for (int ch = 0; ch < 4; ++ch) s[ch] = uint32_t(codes4[ch]);
  } else {
    for (int ch = 0; ch < 4; ++ch) s[ch] = encodeUnorm(source[ch], w, p.rounding);
  }
  loadCodes(p, texel, codes);
  for (int ch = 0; ch < p.channels; ++ch) d[ch] = widenUnormBits(codes[ch], p.bits[ch], w);
  const uint32_t ad = p.hasAlpha ? d[3] : max;
  if (p.lerp) {
    auto lerp = w == 8 ? lerpUnorm8 : lerpUnorm16;
    if (p.writeMask & 1u) {
      const uint32_t sf = factorInteger(state.srcRgb, 0, s, d, ad, p.constant, max);
      const uint32_t df = factorInteger(state.dstRgb, 0, s, d, ad, p.constant, max);
      codes[0] = p.lerpSrc < p.lerpDst ? lerp(sf, d[0], s[0]) : lerp(df, s[0], d[0]);
    }
    storeCodes(p, codes, texel);
    return;
  }
  for (int ch = 0; ch < p.channels; ++ch) {
    if (!(p.writeMask & (1u << ch))) continue;
    const bool alpha = ch == 3;
    const uint32_t sf = factorInteger(alpha ? state.srcAlpha : state.srcRgb, ch, s, d, ad, p.constant, max);
    const uint32_t df = factorInteger(alpha ? state.dstAlpha : state.dstRgb, ch, s, d, ad, p.constant, max);
    const uint32_t r = equationInteger(alpha ? state.equationAlpha : state.equationRgb, s[ch], d[ch], sf, df, w);
    codes[ch] = narrowUnormBits(r, w, p.bits[ch]);
  }
  storeCodes(p, codes, texel);
}

void general(const UnormIntegerPlan& plan, const glm::vec4& source, uint8_t* texel) { run(plan, source, texel); }
template <UnormIntegerBlendFn Blend>
void batchOf(const UnormIntegerPlan& plan, const glm::vec4* const* sources, uint8_t* const* texels, int n) {
  for (int i = 0; i < n; ++i) Blend(plan, *sources[i], texels[i]);
}

// `run` for 8-bit layouts with every channel written, the four channels of a pixel in vector
// lanes (32-bit lanes hold a·b ≤ 255² exactly): factorInteger, equationInteger and
// mulUnormInteger lane by lane, as one vector each. V = v4i: one pixel; V = v8i: two, pixel p's
// channel ch in lane 4p + ch. `alpha`: −1 in the alpha lanes; `ad`: each pixel's destination
// alpha (255 without one) in all its lanes. Lanes past the layout's channels are computed and not
// stored.
// V = v16s: four pixels in 16-bit lanes (RGBA8 runs, compiledRunAvx2; the products below fit
// 16 unsigned bits, the sums and differences 16 signed ones).
typedef int16_t v16s __attribute__((vector_size(32)));
typedef uint16_t v16u __attribute__((vector_size(32)));
template <typename V>
UI_INLINE V eachPixelAlpha(V v) {
  if constexpr (sizeof(V) == 16) return __builtin_shufflevector(v, v, 3, 3, 3, 3);
  else if constexpr (sizeof(v[0]) == 2) return __builtin_shufflevector(v, v, 3, 3, 3, 3, 7, 7, 7, 7, 11, 11, 11, 11, 15, 15, 15, 15);
  else return __builtin_shufflevector(v, v, 3, 3, 3, 3, 7, 7, 7, 7);
}
template <typename V>
UI_INLINE V factor8(BlendFactor f, V s, V d, V ad, V c, V alpha) {
  const FactorRow fr = factorRow(f);
  V v{};
  switch (fr.row) {
    case 0: v = V{}; break;
    case 1: v = s; break;
    case 2: v = alpha ? ad : d; break;
    case 3: v = eachPixelAlpha(s); break;
    case 4: v = ad; break;
    case 5: v = c; break;
    case 6: v = eachPixelAlpha(c); break;
    case 7: {
      const V sa = eachPixelAlpha(s), room = 255 - ad;
      v = alpha ? V{} + 255 : sa < room ? sa : room;
      break;
    }
  }
  return fr.oneMinus ? 255 - v : v;
}
template <typename V>
UI_INLINE V equation8(BlendEquation eq, V s, V d, V sf, V df) {
  auto mul = [](V x, V y) {
    if constexpr (sizeof(x[0]) == 2) {  // ab ≤ 255², and ab + (ab >> 8) + 128 < 2^16: unsigned 16 bits
      const v16u ab = v16u(x) * v16u(y);
      return V((ab + (ab >> 8) + 128) >> 8);
    } else {
      const V ab = x * y;
      return (ab + (ab >> 8) + 128) >> 8;
    }
  };
  V r{};
  switch (eq) {
    case BlendEquation::Add: r = mul(s, sf) + mul(d, df); break;
    case BlendEquation::Subtract: r = mul(s, sf) - mul(d, df); break;
    case BlendEquation::ReverseSubtract: r = mul(d, df) - mul(s, sf); break;
    case BlendEquation::Min: return s < d ? s : d;
    case BlendEquation::Max: return s > d ? s : d;
  }
  r = r < 0 ? 0 : r;
  return r > 255 ? 255 : r;  // saturating, as the integer ops are
}
// The blend of codes s over d (the state's factors per lane: RGB's, alpha's in the alpha lanes).
template <BlendState State, typename V>
UI_INLINE V blendCodes8(V s, V d, V ad, V c) {
  constexpr v4i alphaLane{0, 0, 0, -1};
  V alpha;
  if constexpr (sizeof(V) == 16) alpha = alphaLane;
  else if constexpr (sizeof(alpha[0]) == 2) alpha = V{0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0, -1};
  else alpha = __builtin_shufflevector(alphaLane, alphaLane, 0, 1, 2, 3, 0, 1, 2, 3);
  const V sf = alpha ? factor8(State.srcAlpha, s, d, ad, c, alpha) : factor8(State.srcRgb, s, d, ad, c, alpha);
  const V df = alpha ? factor8(State.dstAlpha, s, d, ad, c, alpha) : factor8(State.dstRgb, s, d, ad, c, alpha);
  const V r = equation8(State.equationRgb, s, d, sf, df);
  if constexpr (State.equationAlpha != State.equationRgb) return alpha ? equation8(State.equationAlpha, s, d, sf, df) : r;
  return r;
}
template <BlendState State, int Channels>
UI_INLINE void run8(const UnormIntegerPlan& p, const glm::vec4& source, uint8_t* texel) {
  const v4i s = encodeUnorm4(load4(source), 8, p.rounding);
  const v4i d{texel[0], Channels > 1 ? texel[1] : 0, Channels > 2 ? texel[2] : 0, Channels == 4 ? texel[3] : 255};
  const v4i ad = Channels == 4 ? eachPixelAlpha(d) : v4i{255, 255, 255, 255};
  const v4i c{int32_t(p.constant[0]), int32_t(p.constant[1]), int32_t(p.constant[2]), int32_t(p.constant[3])};
  storeUnorm8Codes<Channels>(blendCodes8<State>(s, d, ad, c), texel);
}
// run8 on two RGBA8 pixels at once (v8i lanes): the same expressions per lane.
template <BlendState State>
UI_INLINE void run8Pair(const UnormIntegerPlan& p, const glm::vec4& source0, const glm::vec4& source1, uint8_t* texel0,
                        uint8_t* texel1) {
  const v4i s0 = encodeUnorm4(load4(source0), 8, p.rounding), s1 = encodeUnorm4(load4(source1), 8, p.rounding);
  const v8i s = __builtin_shufflevector(s0, s1, 0, 1, 2, 3, 4, 5, 6, 7);
  typedef uint8_t v8u8 __attribute__((vector_size(8)));
  v8u8 bytes;
  std::memcpy(&bytes, texel0, 4), std::memcpy(reinterpret_cast<uint8_t*>(&bytes) + 4, texel1, 4);
  const v8i d = __builtin_convertvector(bytes, v8i);
  const v4i c4{int32_t(p.constant[0]), int32_t(p.constant[1]), int32_t(p.constant[2]), int32_t(p.constant[3])};
  const v8i c = __builtin_shufflevector(c4, c4, 0, 1, 2, 3, 0, 1, 2, 3);
  const v8i r = blendCodes8<State>(s, d, eachPixelAlpha(d), c);
  storeUnorm8Codes<4>(__builtin_shufflevector(r, r, 0, 1, 2, 3), texel0);
  storeUnorm8Codes<4>(__builtin_shufflevector(r, r, 4, 5, 6, 7), texel1);
}

// `run` with the blend state and an 8-bit layout of Channels channels, all written, as
// compile-time constants; the constant and the rounding stay variables.
template <BlendState State, int Channels>
void compiled(const UnormIntegerPlan& plan, const glm::vec4& source, uint8_t* texel) {
  if (!plan.lerp) return run8<State, Channels>(plan, source, texel);
  UnormIntegerPlan p = plan;
  p.state = State;
  p.channels = Channels;
  for (int ch = 0; ch < 4; ++ch) p.bits[ch] = 8;
  p.rgb10a2 = false;
  p.hasAlpha = Channels == 4;
  p.w = 8;
  p.max = 255;
  p.writeMask = (1u << Channels) - 1;
  run(p, source, texel);
}

// The batch of `compiled`: run8 inlined for each pixel of the batch (the pixels are distinct, so
// their order changes nothing), instead of a call through a pointer per pixel. Compiled twice: for
// the build's ISA, and for AVX2 with RGBA8 two pixels at a time (its 256-bit integer operations on
// the pair's lanes; chosen at run time where the CPU has it, the same operations per lane). Split
// into 128-bit halves without AVX2, the pair was slower than one pixel at a time.
template <BlendState State, int Channels, bool Pairs>
UI_INLINE void compiledBatchBody(const UnormIntegerPlan& plan, const glm::vec4* const* sources, uint8_t* const* texels,
                                 int n) {
  if (plan.lerp) {
    for (int i = 0; i < n; ++i) compiled<State, Channels>(plan, *sources[i], texels[i]);
    return;
  }
  int i = 0;
  if constexpr (Pairs && Channels == 4)
    for (; i + 2 <= n; i += 2) run8Pair<State>(plan, *sources[i], *sources[i + 1], texels[i], texels[i + 1]);
  for (; i < n; ++i) run8<State, Channels>(plan, *sources[i], texels[i]);
}
#if defined(__x86_64__)
// A run of RGBA8 texels four pixels at a time: run8's expressions lane for lane, in 16-bit lanes
// (blendCodes8 on v16s), the four texels one load and one store. Returns how many pixels it
// blended (whole groups of four; none for the lerp case, which is one-channel only).
template <BlendState State>
[[gnu::target("avx2")]] int compiledRunAvx2(const UnormIntegerPlan& plan, const glm::vec4* sources, uint8_t* texels, int n) {
  if (plan.lerp) return 0;
  v16s c;
  for (int l = 0; l < 16; ++l) c[l] = int16_t(plan.constant[l % 4]);  // each pixel's four channels
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    __m128i codes[4];
    for (int p = 0; p < 4; ++p) codes[p] = __m128i(encodeUnorm4(load4(sources[i + p]), 8, plan.rounding));
    const v16s s = v16s(_mm256_set_m128i(_mm_packs_epi32(codes[2], codes[3]), _mm_packs_epi32(codes[0], codes[1])));
    uint8_t* t = texels + 4 * size_t(i);
    const v16s d = v16s(_mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(t))));
    const __m256i r = __m256i(blendCodes8<State>(s, d, eachPixelAlpha(d), c));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(t), _mm_packus_epi16(_mm256_castsi256_si128(r), _mm256_extracti128_si256(r, 1)));
  }
  return i;
}
#endif

template <BlendState State, int Channels>
void compiledBatch(const UnormIntegerPlan& plan, const glm::vec4* const* sources, uint8_t* const* texels, int n) {
  compiledBatchBody<State, Channels, false>(plan, sources, texels, n);
}
#if defined(__x86_64__)
template <BlendState State, int Channels>
[[gnu::target("avx2")]] void compiledBatchAvx2(const UnormIntegerPlan& plan, const glm::vec4* const* sources,
                                               uint8_t* const* texels, int n) {
  compiledBatchBody<State, Channels, true>(plan, sources, texels, n);
}
#endif

struct CompiledEntry {
  BlendState state;
  int channels;
  UnormIntegerBlendFn fn;
  UnormIntegerBatchFn batch, batchAvx2;
  UnormIntegerRunFn runAvx2;  // RGBA8 only, else null
};
template <BlendState State, int Channels>
constexpr CompiledEntry entry() {
#if defined(__x86_64__)
  return {State, Channels, &compiled<State, Channels>, &compiledBatch<State, Channels>, &compiledBatchAvx2<State, Channels>,
          Channels == 4 ? &compiledRunAvx2<State> : nullptr};
#else
  return {State, Channels, &compiled<State, Channels>, &compiledBatch<State, Channels>, &compiledBatch<State, Channels>, nullptr};
#endif
}
template <size_t... I>
constexpr auto compiledTable(std::index_sequence<I...>) {
  using states::kMethodBlendStates;
  return std::array<CompiledEntry, 3 * sizeof...(I)>{entry<kMethodBlendStates[I], 1>()...,
                                                      entry<kMethodBlendStates[I], 2>()...,
                                                      entry<kMethodBlendStates[I], 4>()...};
}
constexpr auto kCompiled = compiledTable(std::make_index_sequence<std::size(states::kMethodBlendStates)>());

}  // namespace

UnormIntegerPlan planUnormInteger(const Format& f, const BlendState& state, const glm::vec4& constant,
                                  UnormRounding rounding, unsigned writeMask) {
  UnormIntegerPlan p;
  p.state = state;
  p.channels = f.channels;
  p.rgb10a2 = f.id == FormatId::RGB10A2;
  for (int ch = 0; ch < 4; ++ch) p.bits[ch] = ch < f.channels ? f.unormBits(ch) : 8;
  p.hasAlpha = f.hasAlpha();
  p.w = unormBlendWidth(f);
  p.max = (1u << p.w) - 1;
  p.rounding = rounding;
  for (int ch = 0; ch < 4; ++ch) p.constant[ch] = encodeUnorm(constant[ch], p.w, rounding);
  p.writeMask = writeMask;
  p.lerp = (p.w == 8 || f.unormBits(0) == 16) && isLerpCase(f, state, p.lerpSrc, p.lerpDst);
  return p;
}

namespace {
const CompiledEntry* compiledFor(const UnormIntegerPlan& p) {
  const bool eightBit = !p.rgb10a2 && p.bits[0] == 8 && p.writeMask == (1u << p.channels) - 1;
  if (eightBit)
    for (const CompiledEntry& e : kCompiled)
      if (e.channels == p.channels && e.state.equationRgb == p.state.equationRgb &&
          e.state.equationAlpha == p.state.equationAlpha && e.state.srcRgb == p.state.srcRgb &&
          e.state.dstRgb == p.state.dstRgb && e.state.srcAlpha == p.state.srcAlpha && e.state.dstAlpha == p.state.dstAlpha)
        return &e;
  return nullptr;
}
}  // namespace

UnormIntegerBlendFn unormIntegerBlendFor(const UnormIntegerPlan& p, bool specialised) {
  const CompiledEntry* e = specialised ? compiledFor(p) : nullptr;
  return e ? e->fn : general;
}

UnormIntegerRunFn unormIntegerRunFor(const UnormIntegerPlan& p, bool specialised) {
  const CompiledEntry* e = specialised ? compiledFor(p) : nullptr;
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (e && avx2) return e->runAvx2;
#endif
  return nullptr;
}

UnormIntegerBatchFn unormIntegerBatchFor(const UnormIntegerPlan& p, bool specialised, bool allowAvx2) {
  const CompiledEntry* e = specialised ? compiledFor(p) : nullptr;
  if (!e) return batchOf<general>;
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2 && allowAvx2) return e->batchAvx2;
#endif
  return e->batch;
}

void blendUnormInteger(const Format& f, const BlendState& state, const glm::vec4& constant, UnormRounding rounding,
                       const glm::vec4& source, unsigned writeMask, uint8_t* texel) {
  run(planUnormInteger(f, state, constant, rounding, writeMask), source, texel);
}

}  // namespace oitref::detail
