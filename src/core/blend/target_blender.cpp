#include "blend/target_blender.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <type_traits>
#include <utility>

#include "blend/blend_math.h"
#include "blend/blend_nvidia.h"
#include "blend/method_blend_states.h"
#include "blend/float_texels.h"
#include "format/fp16_inline.h"
#include "format/unorm8_decode.h"

#if defined(__x86_64__)
#include <immintrin.h>  // the AVX2 kernels below (gnu::target), also in builds without AVX
#endif

namespace oitref::detail {
namespace {

// Index of `state` in kMethodBlendStates (blending enabled, every channel written), or -1.
int methodStateIndex(const BlendState& state) {
  for (size_t i = 0; i < std::size(states::kMethodBlendStates); ++i)
    if (states::kMethodBlendStates[i] == state) return int(i);
  return -1;
}


// The fast kernels' texel layouts: how a destination is read into four fp32 lanes and the
// result written back, as decodeTexel and encodeTexel do for these formats.
struct Unorm8Texels {
  static constexpr size_t kChannelBytes = 1;
  static constexpr bool kFixedPoint = true;
  template <int Channels>
  static v4f load(const uint8_t* texel) {
    float d[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    if constexpr (Channels == 4) decodeUnorm8x4(texel, d);
    else
      for (int c = 0; c < Channels; ++c) d[c] = kUnorm8Decode[texel[c]];
    return v4f{d[0], d[1], d[2], d[3]};
  }
  template <int Channels>
  static void store(const Profile& profile, v4f value, uint8_t* texel) {
    storeUnorm8Codes<Channels>(encodeUnorm4(value, 8, profile.unorm), texel);
  }
};
struct HalfTexels {
  static constexpr size_t kChannelBytes = 2;
  static constexpr bool kFixedPoint = false;
  template <int Channels>
  static v4f load(const uint8_t* texel) {
    return loadHalfTexel<Channels>(texel);
  }
  template <int Channels>
  static void store(const Profile& profile, v4f value, uint8_t* texel) {
    uint16_t h[4];
    encodeHalf4Inline(value, profile.fp16, h);
    std::memcpy(texel, h, 2 * Channels);
  }
};
struct Float32Texels {
  static constexpr size_t kChannelBytes = 4;
  static constexpr bool kFixedPoint = false;
  template <int Channels>
  static v4f load(const uint8_t* texel) {
    return loadFloatTexel<Channels>(texel);
  }
  template <int Channels>
  static void store(const Profile&, v4f value, uint8_t* texel) {
    if constexpr (Channels == 4) {  // one 16-byte store, not four of a lane each
      std::memcpy(texel, &value, sizeof value);
      return;
    }
    for (int c = 0; c < Channels; ++c) {
      const float v = value[c];
      std::memcpy(texel + 4 * c, &v, 4);
    }
  }
};

// The conversion alone (blending disabled) into four 8-bit UNORM channels: the rounding rule
// chosen once for the run, not per pixel, and two pixels' codes narrowed and stored together, four
// in a run (each pixel's codes are encodeUnorm4's, so the bits of one pixel at a time).
template <typename Pixels>
void encodeUnorm8Pixels(UnormRounding rounding, const Pixels& pixels, int n) {
  auto run = [&](auto rule) {
    constexpr UnormRounding kRule = decltype(rule)::value;
    int i = 0;
#if defined(__SSE2__)
    if constexpr (std::is_same_v<Pixels, PixelRun<4>>) {  // a run: four pixels' codes in one 16-byte store
      for (; i + 4 <= n; i += 4) {
        const __m128i lo = _mm_packs_epi32(__m128i(encodeUnorm4(load4(pixels.source(i)), 8, kRule)),
                                           __m128i(encodeUnorm4(load4(pixels.source(i + 1)), 8, kRule)));
        const __m128i hi = _mm_packs_epi32(__m128i(encodeUnorm4(load4(pixels.source(i + 2)), 8, kRule)),
                                           __m128i(encodeUnorm4(load4(pixels.source(i + 3)), 8, kRule)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(pixels.texel(i)), _mm_packus_epi16(lo, hi));
      }
    }
    for (; i + 2 <= n; i += 2) {
      const v4i a = encodeUnorm4(load4(pixels.source(i)), 8, kRule), b = encodeUnorm4(load4(pixels.source(i + 1)), 8, kRule);
      const __m128i words = _mm_packs_epi32(__m128i(a), __m128i(b));  // exact for 0..255
      const int64_t bytes = _mm_cvtsi128_si64(_mm_packus_epi16(words, words));
      std::memcpy(pixels.texel(i), &bytes, 4);
      std::memcpy(pixels.texel(i + 1), reinterpret_cast<const char*>(&bytes) + 4, 4);
    }
#endif
    for (; i < n; ++i) storeUnorm8Codes<4>(encodeUnorm4(load4(pixels.source(i)), 8, kRule), pixels.texel(i));
  };
  switch (rounding) {
    case UnormRounding::ExactNearestEven: return run(std::integral_constant<UnormRounding, UnormRounding::ExactNearestEven>{});
    case UnormRounding::Fp32Product: return run(std::integral_constant<UnormRounding, UnormRounding::Fp32Product>{});
    case UnormRounding::NvidiaFixed: return run(std::integral_constant<UnormRounding, UnormRounding::NvidiaFixed>{});
  }
}

// Whether a method state is MAX on every channel (the factors are ignored then).
constexpr bool maxOnEveryChannel(int state) {
  if (state < 0) return false;  // TargetBlender::kRuntimeState
  const BlendState& st = states::kMethodBlendStates[state];
  return st.enabled && st.equationRgb == BlendEquation::Max && st.equationAlpha == BlendEquation::Max;
}

// MAX on an 8-bit UNORM target, in its codes. The float blend clamps the source (NaN to 0), takes
// the maximum with the decoded destination and encodes the result. Clamping and encoding are
// monotone, and every code's decoded value encodes back to that code under each rounding rule
// (test_unorm checks all 256), so encode(max(clamp(s), decode(k))) = max(encode(clamp(s)), k):
// one encoding and one integer maximum per channel instead of decode, blend and encode.
template <int Channels, typename Pixels>
void maxInCodes(UnormRounding rounding, const Pixels& pixels, int n) {
  for (int i = 0; i < n; ++i) {
    const v4i s = encodeUnorm4(load4(pixels.source(i)), 8, rounding);
    uint8_t* t = pixels.texel(i);
#if defined(__SSE4_1__)
    if constexpr (Channels == 4) {  // pack the codes and take the four maxima at once
      uint8_t codes[4];
      storeUnorm8Codes<4>(s, codes);
      uint32_t sc, dc;
      std::memcpy(&sc, codes, 4), std::memcpy(&dc, t, 4);
      const int r = _mm_cvtsi128_si32(_mm_max_epu8(_mm_cvtsi32_si128(int(sc)), _mm_cvtsi32_si128(int(dc))));
      std::memcpy(t, &r, 4);
      continue;
    }
#endif
    for (int c = 0; c < Channels; ++c) t[c] = uint8_t(std::max<int32_t>(s[c], t[c]));
  }
}

// A float target of one or two channels (no alpha), 8 / Channels pixels at a time in eight
// lanes (blendChannelLanes), where the two-pixel loop of fastPixels fills only two or four of
// them; the pixels after the last whole group as one padded group (PaddedGroup).
template <int Channels, bool Half, typename Pixels>
[[gnu::always_inline]] inline void blendChannelGroups(const CompiledBlend& cb, v4f constant, const Pixels& pixels, int n,
                                                       Rounding fp16) {
  using Lanes = std::conditional_t<std::is_same_v<Pixels, PixelPointers>, ScatteredTexelLanes<Channels, Half>,
                                   RunTexelLanes<Channels, Half>>;
  const Lanes lanes{pixels.sources, pixels.texels};
  constexpr int P = 8 / Channels;
  const int whole = n - n % P;
  const PaddedGroup<Channels, Half, Lanes> padded(lanes, whole, n - whole);
  const Lanes tail = padded.lanes();
  for (int i = 0; i < n; i += P) {  // one loop body for both (the blend inlined once)
    const bool last = i == whole;
    const Lanes& px = last ? tail : lanes;
    const int at = last ? 0 : i;
    v8f s, sa, d, da;
    px.loadSources(at, s, sa);
    px.loadDestinations(at, d, da);
    px.store(at, blendChannelLanes<Channels>(cb, s, sa, d, constant), fp16);
  }
  if (whole < n) padded.writeBack(lanes, whole, n - whole);
}

}  // namespace

template <int State>
const CompiledBlend& TargetBlender::compiledBlend(const TargetBlender& b) {
  if constexpr (State == kRuntimeState) {
    return b.compiled_;
  } else {
    static constexpr CompiledBlend compiled = compileBlend(states::kMethodBlendStates[State]);
    return compiled;
  }
}

template <int State>
bool TargetBlender::enabled(const TargetBlender& b) {
  if constexpr (State == kRuntimeState) return b.state_.enabled;
  else return states::kMethodBlendStates[State].enabled;
}

void TargetBlender::useFastKernel(ChannelEncoding encoding, int channels, int stateIndex) {
  // [encoding][channels 1, 2, 4][state + 1]: every combination compiled once.
  constexpr size_t kStates = std::size(states::kMethodBlendStates) + 1;
  const int c = channels == 4 ? 2 : channels - 1;
  const size_t s = size_t(stateIndex + 1);
  auto pick = [&]<size_t... I>(std::index_sequence<I...>) {
    auto table = [&]<typename Texels>() {
      static constexpr Kernel kernels[3][kStates] = {{fastKernel<Texels, 1, int(I) - 1>...},
                                                     {fastKernel<Texels, 2, int(I) - 1>...},
                                                     {fastKernel<Texels, 4, int(I) - 1>...}};
      static constexpr BatchKernel batches[3][kStates] = {{fastBatch<Texels, 1, int(I) - 1>...},
                                                          {fastBatch<Texels, 2, int(I) - 1>...},
                                                          {fastBatch<Texels, 4, int(I) - 1>...}};
      static constexpr RunKernel runs[3][kStates] = {{fastRun<Texels, 1, int(I) - 1>...},
                                                     {fastRun<Texels, 2, int(I) - 1>...},
                                                     {fastRun<Texels, 4, int(I) - 1>...}};
      kernel_ = kernels[c][s], batchKernel_ = batches[c][s], runKernel_ = runs[c][s];
    };
    if (encoding == ChannelEncoding::Unorm) table.template operator()<Unorm8Texels>();
    else if (encoding == ChannelEncoding::Half) table.template operator()<HalfTexels>();
    else table.template operator()<Float32Texels>();
  };
  pick(std::make_index_sequence<kStates>());
}

TargetBlender::TargetBlender(const Format& format, const BlendState& state, const glm::vec4& constant,
                             const Profile& profile, bool allowFastPath, bool smallFloatTargetBound)
    : format_(format), state_(state), compiled_(compileBlend(state)), constant_(format.isUnorm() ? clampUnit4(constant) : constant),
      rawConstant_(constant), profile_(profile) {
  const unsigned all = (1u << format.channels) - 1;
  mask_ = state.writeMask & all;
  texelBytes_ = size_t(format.bytesPerTexel());
  flushDenormals_ = !(smallFloatTargetBound || isSmallFloatFormat(format));
  const bool integer = profile.unormBlend == UnormBlend::Integer && format.isUnorm();
  const bool nvidia = format.id != FormatId::Minifloat &&
                     (format.isUnorm() ? profile.unormBlend == UnormBlend::Nvidia : profile.floatBlend == FloatBlend::Nvidia);
  {
    // keptPixels's case: the composite states on every channel, 8-bit UNORM, fp16 or fp32
    // channels, and a profile whose arithmetic for them is the plain one or llvmpipe's.
    const bool compositeState = state.enabled && (state == states::kComposite || state == states::kPremultipliedOntoBackground);
    const ChannelEncoding e = format.encoding();
    const bool eligibleFormat = (e == ChannelEncoding::Unorm && !format.isPacked() && format.unormBits(0) == 8) ||
                                e == ChannelEncoding::Half || e == ChannelEncoding::Float32;
    skipsEmptyPixels_ = allowFastPath && compositeState && mask_ == all && eligibleFormat && !nvidia;
    floatFlushesDenormals_ = profile.floatBlend == FloatBlend::Llvmpipe && flushDenormals_;
  }
  if (mask_ == 0) use<maskedOffKernel>();
  else if (state.enabled && nvidia) {
    nvidiaPlan_ = planNvidiaBlend(format, state, constant, mask_, allowFastPath);
    use<nvidiaKernel>();
  }
  else if (state.enabled && integer) {
    unormPlan_ = planUnormInteger(format, state, constant, profile.unorm, mask_);
    unormBlend_ = unormIntegerBlendFor(unormPlan_, allowFastPath);
    unormBatch_ = unormIntegerBatchFor(unormPlan_, allowFastPath);
    unormRun_ = unormIntegerRunFor(unormPlan_, allowFastPath);
    kernel_ = integerUnormKernel;
    batchKernel_ = integerUnormBatch;
    runKernel_ = unormRun_ ? integerUnormRun : runThroughBatch;
  } else if (state.enabled && profile.floatBlend == FloatBlend::Llvmpipe && !format.isUnorm()) {
    llvmpipePlan_.shape = llvmpipeFloatShape(format.channels, format.hasAlpha(), state);
    llvmpipePlan_.flushDenormals = flushDenormals_;
    llvmpipePlan_.fma = profile.fma;
    llvmpipePlan_.callerMxcsr = flushDenormals_ ? floatModeOfThisThread() : 0;
    llvmpipeBlend_ = llvmpipeFloatBlendFor(llvmpipePlan_.shape, allowFastPath);
    use<llvmpipeFloatKernel>();
    const int c = format.channels;
    if (allowFastPath && mask_ == all && (c == 1 || c == 2 || c == 4)) {
      llvmpipeTexels_ = llvmpipeFloatTexelsFor(llvmpipePlan_.shape, format.encoding() == ChannelEncoding::Half, allowFastPath);
      if (format.encoding() == ChannelEncoding::Half)
        c == 4 ? useLlvmpipeTexel<4, true>() : c == 2 ? useLlvmpipeTexel<2, true>() : useLlvmpipeTexel<1, true>();
      else if (format.encoding() == ChannelEncoding::Float32)
        c == 4 ? useLlvmpipeTexel<4, false>() : c == 2 ? useLlvmpipeTexel<2, false>() : useLlvmpipeTexel<1, false>();
    }
  } else if (!allowFastPath || mask_ != all) use<genericKernel>();
  else {
    const int c = format.channels;
    switch (format.encoding()) {
      case ChannelEncoding::Unorm:
        if (format.isPacked() || format.unormBits(0) != 8 || (c != 1 && c != 2 && c != 4)) use<genericKernel>();
        else useFastKernel(ChannelEncoding::Unorm, c, methodStateIndex(state));
        break;
      case ChannelEncoding::Half:
      case ChannelEncoding::Float32:
        if (c != 1 && c != 2 && c != 4) use<genericKernel>();
        else useFastKernel(format.encoding(), c, methodStateIndex(state));
        break;
      default: use<genericKernel>();
    }
  }
}

namespace {

// keptPixels's tests: the source's for the whole run first, then one per texel layout, without
// branches inside, for the texels of the empty sources.
inline bool isEmptyPixel(const glm::vec4& source) {  // (+0, +0, +0, 1) exactly
#if defined(__SSE2__)
  const __m128i s = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&source[0]));
  return _mm_movemask_epi8(_mm_cmpeq_epi32(s, _mm_setr_epi32(0, 0, 0, 0x3f800000))) == 0xffff;
#else
  uint32_t s[4];
  std::memcpy(s, &source[0], sizeof s);
  return ((s[0] | s[1] | s[2]) == 0u) & (s[3] == 0x3f800000u);
#endif
}
// Bit i set where sources[i] is (+0, +0, +0, 1), i < n ≤ 64: isEmptyPixel over a run.
uint64_t emptySources(const glm::vec4* sources, int n) {
  uint64_t empty = 0;
  for (int i = 0; i < n; ++i) empty |= uint64_t(isEmptyPixel(sources[i])) << i;
  return empty;
}
#if defined(__x86_64__)
// The same two pixels at a time: each pixel's two 64-bit halves compared at once, the mask's pairs
// of bits folded into one bit each (pext). Half the samples of a composite's blend went to the
// one-pixel test, run for each of its two targets.
[[gnu::target("avx2,bmi2")]] uint64_t emptySourcesAvx2(const glm::vec4* sources, int n) {
  const __m256i pattern = _mm256_setr_epi32(0, 0, 0, 0x3f800000, 0, 0, 0, 0x3f800000);
  uint64_t empty = 0;
  for (int half = 0; half < n; half += 32) {
    const int m = std::min(32, n - half);
    const glm::vec4* s = sources + half;
    uint64_t halves = 0;  // two bits per pixel: its low and high 64 bits as the pattern's
    int i = 0;
    for (; i + 2 <= m; i += 2) {
      const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&s[i][0]));
      halves |= uint64_t(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(v, pattern)))) << (2 * i);
    }
    if (i < m) {
      const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&s[i][0]));
      halves |= uint64_t(_mm_movemask_pd(_mm_castsi128_pd(_mm_cmpeq_epi64(v, _mm256_castsi256_si128(pattern))))) << (2 * i);
    }
    empty |= _pext_u64(halves & (halves >> 1), 0x5555555555555555ull) << half;
  }
  return empty;
}
#endif
// emptySources, two pixels at a time where the CPU can.
uint64_t emptySourcesOfCpu(const glm::vec4* sources, int n) {
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi2");
  if (avx2) return emptySourcesAvx2(sources, n);
#endif
  return emptySources(sources, n);
}

inline bool halfKept(const uint8_t* texel, int channels) {  // not NaN, not −0 (fp16 denormals are kept)
  bool kept = true;
  for (int c = 0; c < channels; ++c) {
    uint16_t h;
    std::memcpy(&h, texel + 2 * c, 2);
    kept &= ((h & 0x7fffu) <= 0x7c00u) & (h != 0x8000u);
  }
  return kept;
}
inline bool floatKept(const uint8_t* texel, int channels, bool flushes) {  // not NaN, not −0, no flushed denormal
  bool kept = true;
  for (int c = 0; c < channels; ++c) {
    uint32_t f;
    std::memcpy(&f, texel + 4 * c, 4);
    const bool denormal = ((f & 0x7f800000u) == 0) & ((f & 0x007fffffu) != 0);
    kept &= ((f & 0x7fffffffu) <= 0x7f800000u) & (f != 0x80000000u) & !(flushes & denormal);
  }
  return kept;
}

// floatKept for four channels, the four tests side by side.
inline bool floatKept4(const uint8_t* texel, bool flushes) {
#if defined(__SSE2__)
  const __m128i f = _mm_loadu_si128(reinterpret_cast<const __m128i*>(texel));
  const __m128i magnitude = _mm_and_si128(f, _mm_set1_epi32(0x7fffffff));
  __m128i bad = _mm_or_si128(_mm_cmpgt_epi32(magnitude, _mm_set1_epi32(0x7f800000)),       // NaN
                             _mm_cmpeq_epi32(f, _mm_set1_epi32(int32_t(0x80000000u))));  // −0
  if (flushes) {
    const __m128i zeroExponent = _mm_cmpeq_epi32(_mm_and_si128(f, _mm_set1_epi32(0x7f800000)), _mm_setzero_si128());
    const __m128i zeroMantissa = _mm_cmpeq_epi32(_mm_and_si128(f, _mm_set1_epi32(0x007fffff)), _mm_setzero_si128());
    bad = _mm_or_si128(bad, _mm_andnot_si128(zeroMantissa, zeroExponent));  // a denormal
  }
  return _mm_movemask_epi8(bad) == 0;
#else
  return floatKept(texel, 4, flushes);
#endif
}

}  // namespace

uint64_t TargetBlender::keptPixels(const glm::vec4* sources, const uint8_t* texels, int n) const {
  if (!skipsEmptyPixels_) return 0;
  const uint64_t empty = emptySourcesOfCpu(sources, n);
  // The texels only of the empty sources: where transparent layers cover the screen, none is
  // read (they were read twice, here and by the blend).
  const int channels = format_.channels;
  const size_t bytes = texelBytes_;
  const bool flushes = floatFlushesDenormals_;
  const ChannelEncoding encoding = format_.encoding();  // the test for the layout chosen once
  auto keepWhere = [&](auto kept) {
    uint64_t result = 0;
    for (uint64_t left = empty; left; left &= left - 1) {
      const int i = __builtin_ctzll(left);
      result |= uint64_t(kept(texels + size_t(i) * bytes)) << i;
    }
    return result;
  };
  if (encoding == ChannelEncoding::Half)
    return keepWhere([channels](const uint8_t* t) { return halfKept(t, channels); });
  if (encoding == ChannelEncoding::Float32 && channels == 4)
    return keepWhere([flushes](const uint8_t* t) { return floatKept4(t, flushes); });
  if (encoding == ChannelEncoding::Float32)
    return keepWhere([channels, flushes](const uint8_t* t) { return floatKept(t, channels, flushes); });
  return empty;  // UNORM8: every code
}

void TargetBlender::blendRunKeeping(const glm::vec4* sources, uint8_t* texels, int n) const {
  // Up to 64 pixels at a time: which ones keep their bits, then the runs between them through
  // the run kernel; the kept ones are not touched.
  for (int start = 0; start < n; start += 64) {
    const int m = std::min(64, n - start);
    const glm::vec4* s = sources + start;
    uint8_t* t = texels + size_t(start) * texelBytes_;
    const uint64_t all = m == 64 ? ~uint64_t(0) : (uint64_t(1) << m) - 1;
    for (uint64_t blend = ~keptPixels(s, t, m) & all; blend;) {
      const int first = __builtin_ctzll(blend);
      const uint64_t from = blend >> first;  // the run of pixels to blend, from `first` on
      const int length = ~from ? __builtin_ctzll(~from) : 64 - first;
      runKernel_(*this, s + first, t + size_t(first) * texelBytes_, length);
      blend &= first + length >= 64 ? 0 : ~uint64_t(0) << (first + length);
    }
  }
}

void TargetBlender::genericKernel(const TargetBlender& b, const glm::vec4& source, uint8_t* texel) {
  const Format& f = b.format_;
  const glm::vec4 result = b.state_.enabled
                               ? store4(blendValues(b.compiled_, load4(source), load4(decodeTexel(f, texel)), load4(b.constant_),
                                                    f.isUnorm(), f.hasAlpha()))
                               : source;
  if (b.mask_ == (1u << f.channels) - 1) {
    encodeTexel(f, result, b.profile_, texel);
    return;
  }
  uint8_t encoded[16];
  encodeTexel(f, result, b.profile_, encoded);
  mergeTexelChannels(f, encoded, texel, b.mask_);
}

void TargetBlender::llvmpipeFloatKernel(const TargetBlender& b, const glm::vec4& source, uint8_t* texel) {
  const Format& f = b.format_;
  const glm::vec4 result =
      store4(b.llvmpipeBlend_(b.llvmpipePlan_, load4(b.rawConstant_), load4(source), load4(decodeTexel(f, texel))));
  uint8_t encoded[16];
  encodeTexel(f, result, b.profile_, encoded);
  mergeTexelChannels(f, encoded, texel, b.mask_);
}

// The same for fp16 and fp32 targets with every channel written, without the per-channel format
// dispatch: decoding (fp16 exactly, via F16C where built with it) and encoding as encodeTexel does.
template <int Channels, bool Half>
void TargetBlender::llvmpipeFloatTexelKernel(const TargetBlender& b, const glm::vec4& source, uint8_t* texel) {
  const v4f d = Half ? loadHalfTexel<Channels>(texel) : loadFloatTexel<Channels>(texel);
  const v4f r = b.llvmpipeBlend_(b.llvmpipePlan_, load4(b.rawConstant_), load4(source), d);
  for (int c = 0; c < Channels; ++c) {
    if constexpr (Half) {
      const uint16_t h = encodeHalfInline(r[c], b.profile_.fp16);
      std::memcpy(texel + 2 * c, &h, 2);
    } else {
      const float v = r[c];
      std::memcpy(texel + 4 * c, &v, 4);
    }
  }
}

// llvmpipeFloatTexelKernel over a batch: groups of 8 / Channels pixels in the eight-lane kernel
// chosen per draw (AVX2; it blends them all), else one pixel at a time. Lane for lane the same
// operations, so the same bits.
template <int Channels, bool Half>
void TargetBlender::llvmpipeFloatTexelBatch(const TargetBlender& b, const glm::vec4* const* sources,
                                            uint8_t* const* texels, int n) {
  int i = b.llvmpipeTexels_.scattered(b.llvmpipePlan_, b.rawConstant_, sources, texels, n, b.profile_.fp16);
  for (; i < n; ++i) llvmpipeFloatTexelKernel<Channels, Half>(b, *sources[i], texels[i]);
}
template <int Channels, bool Half>
void TargetBlender::llvmpipeFloatTexelRun(const TargetBlender& b, const glm::vec4* sources, uint8_t* texels, int n) {
  int i = b.llvmpipeTexels_.run(b.llvmpipePlan_, b.rawConstant_, sources, texels, n, b.profile_.fp16);
  for (; i < n; ++i) llvmpipeFloatTexelKernel<Channels, Half>(b, sources[i], texels + size_t(i) * b.texelBytes_);
}

void TargetBlender::runThroughBatch(const TargetBlender& b, const glm::vec4* sources, uint8_t* texels, int n) {
  constexpr int kGroup = 64;
  const glm::vec4* s[kGroup];
  uint8_t* t[kGroup];
  for (int start = 0; start < n; start += kGroup) {
    const int m = std::min(kGroup, n - start);
    for (int i = 0; i < m; ++i) s[i] = sources + start + i, t[i] = texels + size_t(start + i) * b.texelBytes_;
    b.batchKernel_(b, s, t, m);
  }
}

void TargetBlender::nvidiaKernel(const TargetBlender& b, const glm::vec4& source, uint8_t* texel) {
  blendNvidia(b.nvidiaPlan_, source, texel);
}

void TargetBlender::integerUnormKernel(const TargetBlender& b, const glm::vec4& source, uint8_t* texel) {
  b.unormBlend_(b.unormPlan_, source, texel);
}
void TargetBlender::integerUnormBatch(const TargetBlender& b, const glm::vec4* const* sources, uint8_t* const* texels,
                                      int n) {
  b.unormBatch_(b.unormPlan_, sources, texels, n);
}

void TargetBlender::integerUnormRun(const TargetBlender& b, const glm::vec4* sources, uint8_t* texels, int n) {
  const int done = b.unormRun_(b.unormPlan_, sources, texels, n);
  if (done < n) runThroughBatch(b, sources + done, texels + size_t(done) * b.texelBytes_, n - done);
}

template <typename Texels, int Channels, int State>
void TargetBlender::fastKernel(const TargetBlender& b, const glm::vec4& source, uint8_t* texel) {
  v4f result = load4(source);
  if (enabled<State>(b))
    result = blendValues(compiledBlend<State>(b), result, Texels::template load<Channels>(texel), load4(b.constant_),
                         Texels::kFixedPoint, Channels == 4);
  Texels::template store<Channels>(b.profile_, result, texel);
}

// fastKernel two pixels at a time: blendValues over eight lanes, each lane the operations of
// the one-pixel kernel (so the same bits); an odd pixel alone.
template <typename Texels, int Channels, int State, typename Pixels>
void TargetBlender::fastPixels(const TargetBlender& b, const Pixels& pixels, int n) {
  if (!enabled<State>(b)) {  // the conversion alone, as fastKernel does then
    if constexpr (std::is_same_v<Texels, Unorm8Texels> && Channels == 4) return encodeUnorm8Pixels(b.profile_.unorm, pixels, n);
    for (int i = 0; i < n; ++i) Texels::template store<Channels>(b.profile_, load4(pixels.source(i)), pixels.texel(i));
    return;
  }
  if constexpr (std::is_same_v<Texels, Unorm8Texels> && maxOnEveryChannel(State)) {
    maxInCodes<Channels>(b.profile_.unorm, pixels, n);
    return;
  }
  constexpr bool kFloat = std::is_same_v<Texels, Float32Texels> || std::is_same_v<Texels, HalfTexels>;
  if constexpr (kFloat && Channels < 4) {
    blendChannelGroups<Channels, std::is_same_v<Texels, HalfTexels>>(compiledBlend<State>(b), load4(b.constant_), pixels, n,
                                                                     b.profile_.fp16);
    return;
  }
  int i = 0;
  {
    const v8f constant = twoPixels(load4(b.constant_), load4(b.constant_));
    for (; i + 2 <= n; i += 2) {
      const v8f s = twoPixels(load4(pixels.source(i)), load4(pixels.source(i + 1)));
      const v8f d = twoPixels(Texels::template load<Channels>(pixels.texel(i)),
                              Texels::template load<Channels>(pixels.texel(i + 1)));
      const v8f r = blendValues(compiledBlend<State>(b), s, d, constant, Texels::kFixedPoint, Channels == 4);
      Texels::template store<Channels>(b.profile_, pixelOf(r, 0), pixels.texel(i));
      Texels::template store<Channels>(b.profile_, pixelOf(r, 1), pixels.texel(i + 1));
    }
  }
  for (; i < n; ++i) fastKernel<Texels, Channels, State>(b, pixels.source(i), pixels.texel(i));
}
template <typename Texels, int Channels, int State>
void TargetBlender::fastBatch(const TargetBlender& b, const glm::vec4* const* sources, uint8_t* const* texels, int n) {
  fastPixels<Texels, Channels, State>(b, PixelPointers{sources, texels}, n);
}
template <typename Texels, int Channels, int State>
void TargetBlender::fastRun(const TargetBlender& b, const glm::vec4* sources, uint8_t* texels, int n) {
  fastPixels<Texels, Channels, State>(b, PixelRun<Channels * Texels::kChannelBytes>{sources, texels}, n);
}

}  // namespace oitref::detail
