// Float texels (fp32, or fp16 decoded exactly) as fp32 lanes, shared by the blend kernels of
// target_blender.cpp and the eight-lane llvmpipe kernels of blend_llvmpipe_float.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "blend/blend_math.h"
#include "format/fp16_inline.h"

#if defined(OITREF_HAVE_F16C)
#include <immintrin.h>
#endif

namespace oitref::detail {

// A float texel's channels as four fp32 lanes (absent ones 0, alpha 1), built in registers: put
// together in memory from narrower stores, a 16-byte load of them would wait for the stores to
// retire (no store forwarding), which costs more than the blend.
template <int Channels>
inline v4f loadFloatTexel(const uint8_t* texel) {
  float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  for (int i = 0; i < Channels; ++i) std::memcpy(&c[i], texel + 4 * i, 4);
  return v4f{c[0], c[1], c[2], c[3]};
}
template <int Channels>
inline v4f loadHalfTexel(const uint8_t* texel) {
#if defined(OITREF_HAVE_F16C)
  if constexpr (Channels == 4) return (v4f)decodeHalf4Vector(texel);
#endif
  uint16_t h[4] = {0, 0, 0, 0x3c00};
  for (int i = 0; i < Channels; ++i) std::memcpy(&h[i], texel + 2 * i, 2);
  return decodeHalf4Bits(uint64_t(h[0]) | uint64_t(h[1]) << 16 | uint64_t(h[2]) << 32 | uint64_t(h[3]) << 48);
}
// The lanes of 8 / Channels pixels side by side (the llvmpipe model's eight-lane batch): each
// pixel's first Channels lanes of `px`, and beside every one of them that pixel's lane 3 (its
// alpha: a source's alpha, or the 1 that loadFloatTexel puts there for a target without alpha).
// Built with shuffles in registers, not lane by lane in memory (store forwarding).
template <int Channels>
inline void gatherLanes(const v4f* px, v8f& values, v8f& alphas) {
  if constexpr (Channels == 4) {
    values = __builtin_shufflevector(px[0], px[1], 0, 1, 2, 3, 4, 5, 6, 7);
    alphas = __builtin_shufflevector(px[0], px[1], 3, 3, 3, 3, 7, 7, 7, 7);
  } else if constexpr (Channels == 2) {
    const v4f lo = __builtin_shufflevector(px[0], px[1], 0, 1, 4, 5), hi = __builtin_shufflevector(px[2], px[3], 0, 1, 4, 5);
    const v4f alo = __builtin_shufflevector(px[0], px[1], 3, 3, 7, 7), ahi = __builtin_shufflevector(px[2], px[3], 3, 3, 7, 7);
    values = __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
    alphas = __builtin_shufflevector(alo, ahi, 0, 1, 2, 3, 4, 5, 6, 7);
  } else {
    v4f ra[4];  // pixel pairs: (r_2k, r_2k+1, a_2k, a_2k+1)
    for (int k = 0; k < 4; ++k) ra[k] = __builtin_shufflevector(px[2 * k], px[2 * k + 1], 0, 4, 3, 7);
    const v4f rlo = __builtin_shufflevector(ra[0], ra[1], 0, 1, 4, 5), rhi = __builtin_shufflevector(ra[2], ra[3], 0, 1, 4, 5);
    const v4f alo = __builtin_shufflevector(ra[0], ra[1], 2, 3, 6, 7), ahi = __builtin_shufflevector(ra[2], ra[3], 2, 3, 6, 7);
    values = __builtin_shufflevector(rlo, rhi, 0, 1, 2, 3, 4, 5, 6, 7);
    alphas = __builtin_shufflevector(alo, ahi, 0, 1, 2, 3, 4, 5, 6, 7);
  }
}

// The eight results converted together (fp16: F16C's eight-lane conversion, the rounding of
// encodeHalfInline) into the bytes of 8 / Channels whole texels, in pixel order: written lane by
// lane, the result waited on its own store (store forwarding) and the rounding was tested per channel.
template <bool Half>
[[gnu::always_inline]] inline void encodeLanes(v8f r, Rounding fp16, uint8_t* out) {
  if constexpr (Half) {
#if defined(OITREF_HAVE_F16C)
    const __m128i packed = fp16 == Rounding::TowardZero
                               ? _mm256_cvtps_ph((__m256)r, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)
                               : _mm256_cvtps_ph((__m256)r, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), packed);
#else
    for (int l = 0; l < 8; ++l) {
      const uint16_t h = encodeHalfInline(r[l], fp16);
      std::memcpy(out + 2 * l, &h, 2);
    }
#endif
  } else {
    std::memcpy(out, &r, sizeof r);
  }
}

// Where the pixels of a batch are (every fast kernel's loop reads them through one of these): a
// pointer per pixel to its source and its texel (any pixels), or a run of consecutive texels of
// Bytes bytes with the sources side by side (a span whose every fragment blends:
// TargetBlender::blendRun).
struct PixelPointers {
  const glm::vec4* const* sources;
  uint8_t* const* texels;
  const glm::vec4& source(int i) const { return *sources[i]; }
  uint8_t* texel(int i) const { return texels[i]; }
};
template <size_t Bytes>
struct PixelRun {
  const glm::vec4* sources;
  uint8_t* texels;
  const glm::vec4& source(int i) const { return sources[i]; }
  uint8_t* texel(int i) const { return texels + size_t(i) * Bytes; }
};

// The same pixels for the eight-lane kernels of float texels (blend_llvmpipe_float.cpp, and
// target_blender.cpp's for targets of one or two channels), which take 8 / Channels pixels a
// group: ScatteredTexelLanes for PixelPointers, RunTexelLanes for a PixelRun, whose group's
// texels are one load and one store. Both put group g's (pixels g·P … g·P + P − 1, P = 8 /
// Channels) sources and destinations into lanes as gatherLanes arranges them, and store its
// results; the lanes are the same either way.
template <int Channels, bool Half>
struct ScatteredTexelLanes : PixelPointers {
  static constexpr int P = 8 / Channels;
  ScatteredTexelLanes from(int i) const { return {sources + i, texels + i}; }  // pixels [i, …)
  [[gnu::always_inline]] inline void loadSources(int i, v8f& values, v8f& alphas) const {
    v4f s[P];
    for (int p = 0; p < P; ++p) s[p] = load4(*sources[i + p]);
    gatherLanes<Channels>(s, values, alphas);
  }
  [[gnu::always_inline]] inline void loadDestinations(int i, v8f& values, v8f& alphas) const {
    v4f d[P];
    for (int p = 0; p < P; ++p)
      d[p] = Half ? loadHalfTexel<Channels>(texels[i + p]) : loadFloatTexel<Channels>(texels[i + p]);
    gatherLanes<Channels>(d, values, alphas);
  }
  [[gnu::always_inline]] inline void store(int i, v8f r, Rounding fp16) const {
    constexpr size_t bytes = (Half ? 2 : 4) * Channels;
    alignas(32) uint8_t out[8 * (Half ? 2 : 4)];
    encodeLanes<Half>(r, fp16, out);
    for (int p = 0; p < P; ++p) std::memcpy(texels[i + p], out + p * bytes, bytes);
  }
};
template <int Channels, bool Half>
struct RunTexelLanes : PixelRun<(Half ? 2 : 4) * Channels> {
  static constexpr int P = 8 / Channels;
  static constexpr size_t kTexelBytes = (Half ? 2 : 4) * Channels;
  using PixelRun<kTexelBytes>::sources;
  using PixelRun<kTexelBytes>::texels;
  RunTexelLanes from(int i) const { return {sources + i, texels + size_t(i) * kTexelBytes}; }
  [[gnu::always_inline]] inline void loadSources(int i, v8f& values, v8f& alphas) const {
    if constexpr (Channels == 4) {  // two pixels' vec4s are the lanes already
      std::memcpy(&values, sources + i, sizeof values);
      alphas = __builtin_shufflevector(values, values, 3, 3, 3, 3, 7, 7, 7, 7);
    } else if constexpr (Channels == 1) {
      // Eight pixels' vec4s as four pairs, their r and a picked out by shuffles within the
      // halves, then put in pixel order: gatherLanes's lanes with four loads instead of eight.
      // (Four named vectors: loaded into an array, GCC copied them through the stack first.)
      v8f p01, p23, p45, p67;
      std::memcpy(&p01, sources + i, sizeof p01), std::memcpy(&p23, sources + i + 2, sizeof p23);
      std::memcpy(&p45, sources + i + 4, sizeof p45), std::memcpy(&p67, sources + i + 6, sizeof p67);
      const v8f ra01 = __builtin_shufflevector(p01, p23, 0, 3, 8, 11, 4, 7, 12, 15);  // r0 a0 r2 a2 | r1 a1 r3 a3
      const v8f ra23 = __builtin_shufflevector(p45, p67, 0, 3, 8, 11, 4, 7, 12, 15);  // r4 a4 r6 a6 | r5 a5 r7 a7
      values = __builtin_shufflevector(ra01, ra23, 0, 4, 2, 6, 8, 12, 10, 14);
      alphas = __builtin_shufflevector(ra01, ra23, 1, 5, 3, 7, 9, 13, 11, 15);
    } else {
      v4f s[P];
      for (int p = 0; p < P; ++p) s[p] = load4(sources[i + p]);
      gatherLanes<Channels>(s, values, alphas);
    }
  }
  [[gnu::always_inline]] inline void loadDestinations(int i, v8f& values, v8f& alphas) const {
    const uint8_t* t = texels + size_t(i) * kTexelBytes;
    if constexpr (Half) {
#if defined(OITREF_HAVE_F16C)
      values = (v8f)_mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(t)));
#else
      float f[8];
      decodeHalvesInline(t, 8, f);
      std::memcpy(&values, f, sizeof values);
#endif
    } else {
      std::memcpy(&values, t, sizeof values);
    }
    // Each lane's pixel's alpha: lane 3 of a four-channel texel, else the 1 of a target without alpha.
    if constexpr (Channels == 4) alphas = __builtin_shufflevector(values, values, 3, 3, 3, 3, 7, 7, 7, 7);
    else alphas = splatLanes<v8f>(1.0f);
  }
  [[gnu::always_inline]] inline void store(int i, v8f r, Rounding fp16) const {
    encodeLanes<Half>(r, fp16, texels + size_t(i) * kTexelBytes);
  }
};

// The last n < P pixels of a batch (from `first` on) as one whole group of local texels, so that
// they take the eight-lane blend too instead of one pixel at a time (a span's last 0 to 7
// pixels of a one-channel target: about an eighth of its pixels). The missing lanes repeat the
// last pixel; a lane's bits do not depend on the others', and those lanes are not written back.
// lanes() views it as the batch's own Pixels type (ScatteredTexelLanes or RunTexelLanes), so that
// a kernel blends it with the same code as every other group: a second type inlined the whole
// blend a second time into every kernel (twice the compile time). With n = 0 it holds nothing.
template <int Channels, bool Half, typename Pixels>
class PaddedGroup {
 public:
  static constexpr int P = 8 / Channels;
  static constexpr size_t kTexelBytes = (Half ? 2 : 4) * Channels;

  PaddedGroup(const Pixels& pixels, int first, int n) {
    for (int p = 0; n > 0 && p < P; ++p) {
      const int i = first + (p < n ? p : n - 1);
      sources_[p] = pixels.source(i);
      std::memcpy(texels_ + p * kTexelBytes, pixels.texel(i), kTexelBytes);
      if constexpr (kScattered) sourcePointers_[p] = &sources_[p], texelPointers_[p] = texels_ + p * kTexelBytes;
    }
  }
  PaddedGroup(const PaddedGroup&) = delete;  // lanes() points into it
  PaddedGroup& operator=(const PaddedGroup&) = delete;

  Pixels lanes() const {
    if constexpr (kScattered) return {sourcePointers_, texelPointers_};
    else return {sources_, const_cast<uint8_t*>(texels_)};
  }
  void writeBack(const Pixels& pixels, int first, int n) const {
    for (int p = 0; p < n; ++p) std::memcpy(pixels.texel(first + p), texels_ + p * kTexelBytes, kTexelBytes);
  }

 private:
  static constexpr bool kScattered = std::is_same_v<Pixels, ScatteredTexelLanes<Channels, Half>>;
  glm::vec4 sources_[P];
  alignas(32) uint8_t texels_[P * kTexelBytes];
  const glm::vec4* sourcePointers_[kScattered ? P : 1];
  uint8_t* texelPointers_[kScattered ? P : 1];
};

}  // namespace oitref::detail
