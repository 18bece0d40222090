// Float texels (fp32, or fp16 decoded exactly) as fp32 lanes, shared by the blend kernels of
// target_blender.cpp and the eight-lane llvmpipe kernels of blend_llvmpipe_float.cpp.
#pragma once

#include <cstdint>
#include <cstring>

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

}  // namespace oitref::detail
