// Blending and the colour write: the one place where a fragment's colour meets a stored texel.
// The pipeline's fragment operations and `oitref blend` both call blendIntoTexel.
//
// Rules (GL 4.6 §17.3.6, "Blending"):
//  * Fixed-point (UNORM) targets: the source colour, the destination, the blend constant and
//    therefore every factor are clamped to [0,1] (NaN -> 0) before the equation; the result is
//    clamped to [0,1] and converted by the profile's UNORM rule (§17.3.6.1, §17.3.6.5).
//  * Floating-point targets: no clamping anywhere.
//  * Factors (table 17.2); for the alpha channel the colour factors use the alpha component.
//    SRC_ALPHA_SATURATE: f = min(As, 1 − Ad) for RGB, 1 for alpha. A target without an alpha
//    channel reads Ad = 1 (§17.3.6.6).
//  * Equations (table 17.1) in fp32, evaluated as written — s·Sf and d·Df rounded separately, then
//    added (no fused multiply-add; the build disables contraction). IEEE arithmetic throughout,
//    so 0·inf = NaN; a NaN result is stored as the canonical quiet NaN (positive, quiet bit only),
//    since NaN signs and payloads from arithmetic differ between CPUs. MIN/MAX ignore the factors; they return the non-NaN operand when exactly one
//    is NaN (IEEE minNum/maxNum) and the source when the operands compare equal.
//  * The result is quantised to the format immediately (every write is a conversion), then
//    channels whose write-mask bit is clear keep their old bits (§17.4.2).
//  * With blending disabled the source is converted and written under the write mask.
//  * Profile "llvmpipe" with unorm_blend=integer: UNORM targets blend in integers of w bits as
//    Mesa's llvmpipe does (w = 8 for r8, rg8, rgba8; 16 for rgb10a2): source and constant
//    quantised to w bits first by the profile's UNORM rule, stored channels widened by bit
//    replication, a·b/(2^w−1) as llvmpipe's lp_build_mul_norm computes it (the rule is stated
//    once, in mulUnormInteger, src/core/blend/blend_unorm_integer.h), 1 − x as 2^w−1 − x, ADD
//    saturating at the maximum and SUBTRACT at 0, the result narrowed to the channel's bits as
//    src/core/format/unorm_rescale.h says.
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "oitref/core/blend_state.h"
#include "oitref/core/format.h"
#include "oitref/core/profile.h"

namespace oitref {

// Blends `source` into the texel's bytes in place (under the default floating-point environment).
void blendIntoTexel(const Format& format, const BlendState& state, const glm::vec4& constant,
                    const Profile& profile, const glm::vec4& source, uint8_t* texel);

// The fp32 blend of already-decoded values, before quantisation (UNORM clamping included).
// Exposed so tests and tools can show the unrounded result.
glm::vec4 blendFloat(const BlendState& state, const glm::vec4& source, const glm::vec4& destination,
                     const glm::vec4& constant, bool fixedPoint, bool targetHasAlpha);

}  // namespace oitref
