// llvmpipe-style blending of 8-bit UNORM targets in integer arithmetic (see oitref/blend.h).
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "oitref/blend_state.h"
#include "oitref/unorm.h"

namespace oitref::detail {

// a·b/255 rounded the way llvmpipe's lp_build_mul_norm does for 8 bits.
inline uint32_t mulUnorm8(uint32_t a, uint32_t b) {
  const uint32_t t = a * b + 128;
  return (t + (t >> 8)) >> 8;
}

void blendUnorm8Integer(int channels, const BlendState& state, const glm::vec4& constant, UnormRounding rounding,
                        const glm::vec4& source, unsigned writeMask, uint8_t* texel);

}  // namespace oitref::detail
