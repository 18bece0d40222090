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
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "oitref/blend_state.h"
#include "oitref/format.h"
#include "oitref/profile.h"

namespace oitref::detail {

// The blended value of the texel's channels (fp32, before conversion into the format).
// `flushDenormals`: llvmpipe sets DAZ and FTZ for the fragment code unless the draw writes a
// small-float target (fp16, r11g11b10f), whose conversions need denormals.
glm::vec4 blendLlvmpipeFloat(const Format& format, const BlendState& state, const glm::vec4& constant, bool fma,
                             bool flushDenormals, const glm::vec4& source, const glm::vec4& destination);

}  // namespace oitref::detail
