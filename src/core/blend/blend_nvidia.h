// NVIDIA Hopper's blender (profile nvidia). Every rule below was found on recorded GPU results
// (an H200 and an H100, driver 580.159.04; the cases and the experiments that pin each rule are in
// docs/rules.md, "Profile nvidia", and tests/data/nvidia/).
//
// UNORM targets (r8…rgba8, r16…rgba16, rgb10a2) blend exactly on b-bit codes:
//  * source and constant are converted like a stored value (UnormRounding::NvidiaFixed); every
//    rgb10a2 channel, alpha included, is a 10-bit code (a stored 2-bit alpha a reads as 341·a);
//  * factors are codes too: 1 − x is (2^b − 1) − x, SRC_ALPHA_SATURATE min(As, (2^b − 1) − Ad);
//  * the result is the exact s·Sf ± d·Df divided by (2^b − 1)², clamped to [0, 1] and rounded to
//    the nearest code (no ties exist); MIN/MAX compare codes; rgb10a2's alpha is then narrowed to
//    two bits (nvidiaAlpha2From10).
// Float targets blend in their own precision p: 24 bits for r32f…rgba32f, 11 for r16f…rgba16f and
// r11g11b10f (whose source and constant are first converted to fp16, rounding toward zero):
//  * fp32 operands are read with denormals as zero (DAZ) and denormal results are flushed (FTZ);
//  * 1 − x is rounded to p bits (nearest even; a NaN x gives +NaN); SRC_ALPHA_SATURATE is
//    minNum(As, 1 − Ad) with −0 below +0 — as the colour destination factor it is zero when As is
//    zero and the alpha destination factor evaluates to zero;
//  * zero times anything (inf, NaN) is zero; a ZERO factor is never evaluated;
//  * the two products s·Sf and d·Df are exact; each is rounded to odd at the position 2^(e−p−4),
//    e being the larger of the two products' exponent estimates exp(x) + exp(y) (frexp exponents:
//    the product lies in [2^(e−2), 2^e)); the sum T of the two is exact; if T's last place (p bits
//    below its leading bit, or fp16's denormal grid) falls below 2^(e−p−2), its last bit (the
//    sticky) is dropped, else it is rounded to nearest even; the r11g11b10f channels then take that
//    fp16 value toward zero; NaN results are 0x7fffffff (0x7fff);
//  * a sum of two exact zeros takes the sign of the destination term when the destination value
//    is zero and its factor is not, else the sign of the source term, whose DST_COLOR factor keeps
//    its sign out when the source colour (as converted) is zero in the target's colour channels;
//    x − x is +0;
//  * MIN/MAX are minNum/maxNum of the operands (−0 below +0);
//  * the blend is skipped, every destination bit kept, when the source cannot change a destination
//    in [0, 1] (leavesDestination in the .cpp).
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "oitref/core/blend_state.h"
#include "oitref/core/format.h"
#include "oitref/core/minifloat.h"

namespace oitref::detail {

// Blends `source` into the texel; channels outside `mask` keep their bits. `state.enabled`.
// The rules above, one fragment at a time: the oracle of the planned kernels below.
void blendNvidia(const Format& format, const BlendState& state, const glm::vec4& constant, const glm::vec4& source,
                 unsigned mask, uint8_t* texel);

// One target's blend in a draw, decided once: rgba8/rgba16 with their widths compiled in, and for
// fp32/fp16 targets of 1, 2 or 4 channels written whole a kernel for the usual fragment (finite,
// not denormal, a non-zero source alpha, no zero sum) that hands every other fragment to
// blendNvidia. Same bits.
struct NvidiaBlendPlan {
  Format format;
  BlendState state;
  glm::vec4 constant;
  unsigned mask = 0;
  glm::vec4 convertedConstant{0.0f};  // as the float blend reads it (DAZ, or fp16 toward zero)
  // The draw's state per channel lane (lane 3 alpha's; lanes without a channel: zeros, signs 1).
  struct Lanes {
    BlendFactor source[2] = {BlendFactor::One, BlendFactor::One};  // colour, alpha
    BlendFactor destination[2] = {BlendFactor::One, BlendFactor::One};
    int32_t foldSource[4] = {}, foldDestination[4] = {};  // −1: the factor is ZERO (the term left out)
    int32_t minMax[4] = {}, isMin[4] = {};                 // −1: MIN or MAX; MIN
    int32_t addLike[4] = {};                               // −1: ADD or REVERSE_SUBTRACT
    int32_t destinationOne[4] = {}, oneIfSourceZero[4] = {};  // −1: ONE; ONE_MINUS_SRC_COLOR
    double signSource[4] = {1, 1, 1, 1}, signDestination[4] = {1, 1, 1, 1};  // −1: the term subtracted
  } lanes;
  Rounding halfRounding = Rounding::NearestEven;
  void (*blend)(const NvidiaBlendPlan&, const glm::vec4& source, uint8_t* texel) = nullptr;
};
using NvidiaBlendFn = void (*)(const NvidiaBlendPlan&, const glm::vec4& source, uint8_t* texel);
NvidiaBlendPlan planNvidiaBlend(const Format& format, const BlendState& state, const glm::vec4& constant, unsigned mask,
                                bool allowFastPath = true);
inline void blendNvidia(const NvidiaBlendPlan& plan, const glm::vec4& source, uint8_t* texel) {
  plan.blend(plan, source, texel);
}
// The usual-fragment kernel for an fp32 (else fp16) target of 1, 2 or 4 channels
// (blend_nvidia_lanes.cpp).
NvidiaBlendFn nvidiaUsualFloatKernel(bool fp32, int channels);

}  // namespace oitref::detail
