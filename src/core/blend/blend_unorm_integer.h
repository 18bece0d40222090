// llvmpipe's integer path for UNORM targets (profile key unorm_blend=integer; see docs/rules.md).
//
// llvmpipe (Mesa 22.3, lp_state_fs.c) blends a UNORM target in integers of a "blend width" w:
// the widest channel rounded up to 8 or 16 bits, so w = 8 for r8/rg8/rgba8 and w = 16 for
// rgb10a2. The fp32 source and constant are converted to w bits (the fp32-product rule); stored
// channels of n < w bits are widened by bit replication; a·b/(2^w − 1) is computed as
// mulUnormInteger below states it; the result is narrowed back to n bits with
// llvmpipe's scale_bits: a plain right shift when w − n ≤ n (rgb10a2's colour: truncation), and
// ((v >> n)·(2^n − 1) + 2^(w−n−1)) >> (w − n) otherwise (rgb10a2's 2-bit alpha). Writes with
// blending off take the same conversion and narrowing.
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "oitref/core/blend_state.h"
#include "oitref/core/format.h"
#include "oitref/core/unorm.h"
#include "format/unorm_rescale.h"

namespace oitref::detail {

// a·b/(2^w − 1) as llvmpipe's lp_build_mul_norm computes it: (ab + (ab >> w) + 2^(w−1)) >> w
// with ab = a·b. Measured against llvmpipe on all 65536 8-bit pairs: it rounds down the 24
// products whose exact quotient is k + 0.502 (e.g. 244·197/255 = 188.502 → 188).
inline uint32_t mulUnormInteger(uint32_t a, uint32_t b, int w) {
  const uint64_t ab = uint64_t(a) * b;
  return uint32_t((ab + (ab >> w) + (uint64_t(1) << (w - 1))) >> w);
}
inline uint32_t mulUnorm8(uint32_t a, uint32_t b) { return mulUnormInteger(a, b, 8); }

// What llvmpipe fixes when it compiles a draw's blend for one UNORM target: the layout, the blend
// width, the constant in w bits, and whether the one-channel lerp applies.
struct UnormIntegerPlan {
  BlendState state;
  int channels = 4;
  int bits[4] = {8, 8, 8, 8};  // stored bits per channel
  bool rgb10a2 = false, hasAlpha = true;
  int w = 8;
  uint32_t max = 255;
  uint32_t constant[4] = {0, 0, 0, 0};  // in w bits
  UnormRounding rounding = UnormRounding::Fp32Product;
  unsigned writeMask = 0xf;
  bool lerp = false;  // one channel, complementary factors, ADD: lp_build_lerp
  unsigned lerpSrc = 0, lerpDst = 0;  // the sanitised Gallium factors of the lerp
};
UnormIntegerPlan planUnormInteger(const Format& format, const BlendState& state, const glm::vec4& constant,
                                  UnormRounding rounding, unsigned writeMask);

// Blends `source` into the texel as the plan says.
using UnormIntegerBlendFn = void (*)(const UnormIntegerPlan&, const glm::vec4& source, uint8_t* texel);
// The general function, or one compiled for the plan's blend state and 8-bit layout when the state
// is a method blend state (method_blend_states.h): the same bits. `specialised` false: the general one.
UnormIntegerBlendFn unormIntegerBlendFor(const UnormIntegerPlan& plan, bool specialised = true);
// The same over a batch: sources[i] into texels[i], i < n, one call (the per-texel function
// inlined into the loop). A compiled batch has a variant for AVX2, taken where the CPU has it;
// `allowAvx2` false asks for the build's own (the tests run both).
using UnormIntegerBatchFn = void (*)(const UnormIntegerPlan&, const glm::vec4* const* sources, uint8_t* const* texels,
                                     int n);
UnormIntegerBatchFn unormIntegerBatchFor(const UnormIntegerPlan& plan, bool specialised = true, bool allowAvx2 = true);
// Over a run of consecutive RGBA8 texels: sources[i] into the i-th texel for the first whole
// groups of four pixels of [0, n) (16-bit lanes, AVX2); returns how many that was, the caller
// blends the rest. Null where there is none (not RGBA8, not a method state, no AVX2).
using UnormIntegerRunFn = int (*)(const UnormIntegerPlan&, const glm::vec4* sources, uint8_t* texels, int n);
UnormIntegerRunFn unormIntegerRunFor(const UnormIntegerPlan& plan, bool specialised = true);

void blendUnormInteger(const Format& format, const BlendState& state, const glm::vec4& constant, UnormRounding rounding,
                       const glm::vec4& source, unsigned writeMask, uint8_t* texel);

}  // namespace oitref::detail
