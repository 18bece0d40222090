// llvmpipe's blending of floating-point targets (profile key float_blend=llvmpipe; see
// docs/rules.md, "Profile llvmpipe"). Mesa 22.3's llvmpipe builds the blend per draw from
// lp_build_blend_aos and lp_build_blend (lp_bld_blend*.c), which differ from GL's
// s·Sf ⊕ d·Df evaluated literally in ways visible in the bits:
//  * factor vectors that are the constant 0 or 1 in every lane are folded away: s·0 is not
//    computed (so −0, inf·0 and NaN·0 never arise) and x + 0 returns x;
//  * targets without alpha: DST_ALPHA → ONE, ONE_MINUS_DST_ALPHA → ZERO, and the RGB
//    SRC_ALPHA_SATURATE factor is min(As, 0);
//  * MIN and MAX take ONE factors and x86 minps/maxps semantics (a < b ? a : b);
//  * when the factors do not depend on the channel (see `factorsChannelIndependent`):
//    complementary factors with ADD become a lerp d + Sf·(s − d) computed with a fused
//    multiply-add (profile key fma), with SUBTRACT (s + d)·Sf − d, with REVERSE_SUBTRACT
//    d − (s + d)·Sf (mirrored when the source factor is the inverted one); equal factors give
//    (s ⊕ d)·F.
// Like llvmpipe, oitref makes these decisions once per draw (LlvmpipeFloatPlan) and runs a blend
// function compiled for the draw's state where it is one the methods use.
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "oitref/core/blend_state.h"
#include "oitref/core/format.h"
#include "oitref/core/profile.h"
#include "blend/blend_math.h"
#include "blend/llvmpipe_factors.h"

namespace oitref::detail {

// What llvmpipe decides when it compiles a draw's blend (lp_state_fs.c, lp_bld_blend*.c): the
// factors in Gallium numbering after Mesa's rewrites (MIN/MAX take ONE; without alpha, DST_ALPHA
// is ONE and the alpha equation is the RGB one), the layout, and whether the factors are the same
// for every channel. Two plans with equal shapes blend alike.
struct LlvmpipeFloatShape {
  unsigned rs = 0, rd = 0, as = 0, ad = 0;
  BlendEquation eqRgb = BlendEquation::Add, eqAlpha = BlendEquation::Add;
  int channels = 4;
  bool hasAlpha = true;
  bool independent = false;
  constexpr bool operator==(const LlvmpipeFloatShape&) const = default;
};
constexpr LlvmpipeFloatShape llvmpipeFloatShape(int channels, bool hasAlpha, const BlendState& state);

// `flushDenormals`: llvmpipe sets DAZ and FTZ for the fragment code unless the draw writes a
// small-float target (fp16, r11g11b10f), whose conversions need denormals. `fma`: profile key fma.
struct LlvmpipeFloatPlan {
  LlvmpipeFloatShape shape;
  bool flushDenormals = true, fma = false;
  // x86: the MXCSR of the thread that made the plan (floatModeOfThisThread), which the eight-lane
  // kernels put back after each chunk they blend with DAZ and FTZ set: reading it per call cost as
  // much as the chunk's blend. 0: read per call. A plan is used on the thread that made it, or on
  // one in the same floating-point mode (the renderer's workers run in their arena's).
  uint32_t callerMxcsr = 0;
};
// The calling thread's MXCSR on x86 (LlvmpipeFloatPlan::callerMxcsr), else 0.
uint32_t floatModeOfThisThread();

// Blends fp32 `source` and `destination` (the texel decoded) as the plan says; the result is
// converted into the format by the caller.
// The four lanes travel in vector registers (blend_math.h's v4f).
using LlvmpipeFloatBlendFn = v4f (*)(const LlvmpipeFloatPlan&, v4f constant, v4f source, v4f destination);

// Texels of an fp16 (`half`) or fp32 target with every channel written, blended in eight lanes:
// the channels of 8 / channels pixels side by side (rgba: two pixels, rg: four, r: eight), each
// lane's pixel's alphas beside them, lane for lane the bits of LlvmpipeFloatBlendFn on each pixel,
// and the results converted as encodeTexel does (fp16 rounded as `fp16`). Blends *sources[i]
// into texels[i] for every i in [0, n), the pixels after the last whole group as one padded group
// (PaddedGroup), and returns n. Compiled for AVX2, with the loop inside, so that
// nothing crosses a call per group; `constant` travels by reference (between code built with
// and without AVX, a 32-byte vector passed by value would not be where the other side looks).
using LlvmpipeFloatTexelsFn = int (*)(const LlvmpipeFloatPlan& plan, const glm::vec4& constant,
                                      const glm::vec4* const* sources, uint8_t* const* texels, int n, Rounding fp16);
// The same over a run of n consecutive texels starting at `texels`, sources[i] blended into the
// i-th: each group's texels one load and one store. The same bits.
using LlvmpipeFloatRunFn = int (*)(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* sources,
                                   uint8_t* texels, int n, Rounding fp16);
struct LlvmpipeFloatTexelFns {
  LlvmpipeFloatTexelsFn scattered = nullptr;
  LlvmpipeFloatRunFn run = nullptr;
};

// The general function, and one compiled for the plan's shape when it is that of a method blend
// state (method_blend_states.h), with the same bits; `specialised` false always gives the general one.
LlvmpipeFloatBlendFn llvmpipeFloatBlendFor(const LlvmpipeFloatShape& shape, bool specialised = true);
// The eight-lane texel functions: null where the CPU lacks AVX2 (then blend pixel by pixel).
LlvmpipeFloatTexelFns llvmpipeFloatTexelsFor(const LlvmpipeFloatShape& shape, bool half, bool specialised = true);

// The blended value of the texel's channels (fp32, before conversion into the format).
glm::vec4 blendLlvmpipeFloat(const Format& format, const BlendState& state, const glm::vec4& constant, bool fma,
                             bool flushDenormals, const glm::vec4& source, const glm::vec4& destination);

constexpr LlvmpipeFloatShape llvmpipeFloatShape(int channels, bool hasAlpha, const BlendState& state) {
  LlvmpipeFloatShape s;
  s.channels = channels;
  s.hasAlpha = hasAlpha;
  s.rs = pipeFactor(state.srcRgb), s.rd = pipeFactor(state.dstRgb);
  s.as = pipeFactor(state.srcAlpha), s.ad = pipeFactor(state.dstAlpha);
  // Mesa's state tracker: MIN and MAX ignore the factors, so it sets them to ONE.
  auto isMinMax = [](BlendEquation e) { return e == BlendEquation::Min || e == BlendEquation::Max; };
  if (isMinMax(state.equationRgb)) s.rs = s.rd = kPipeOne;
  if (isMinMax(state.equationAlpha)) s.as = s.ad = kPipeOne;
  s.eqRgb = state.equationRgb;
  s.eqAlpha = state.equationAlpha;
  // llvmpipe (lp_state_fs.c): without a destination alpha channel, Ad = 1 is folded into the
  // RGB factors, and the alpha equation and factors are made the RGB ones.
  if (!hasAlpha) {
    for (unsigned* f : {&s.rs, &s.rd}) {
      if (*f == kPipeDstAlpha) *f = kPipeOne;
      else if (*f == kPipeInvDstAlpha) *f = kPipeZero;
    }
    s.as = s.rs, s.ad = s.rd, s.eqAlpha = s.eqRgb;
  }
  s.independent = (s.rs == s.rd && s.as == s.ad) || channels == 1;
  return s;
}

}  // namespace oitref::detail
