// Gallium's PIPE_BLENDFACTOR numbering, which llvmpipe's blend code reasons about: an inverted
// factor is its base ^ 0x10, and ZERO is ONE's inverse. Shared by the llvmpipe profile's float
// and integer blend models.
#pragma once

#include <cstddef>

#include "oitref/core/blend_state.h"

namespace oitref::detail {

enum PipeFactor : unsigned {
  kPipeOne = 0x01, kPipeSrcColor = 0x02, kPipeSrcAlpha = 0x03, kPipeDstAlpha = 0x04, kPipeDstColor = 0x05,
  kPipeSrcAlphaSaturate = 0x06, kPipeConstColor = 0x07, kPipeConstAlpha = 0x08, kPipeZero = 0x11,
  kPipeInvSrcColor = 0x12, kPipeInvSrcAlpha = 0x13, kPipeInvDstAlpha = 0x14, kPipeInvDstColor = 0x15,
  kPipeInvConstColor = 0x17, kPipeInvConstAlpha = 0x18,
};

constexpr unsigned pipeFactor(BlendFactor f) {
  constexpr unsigned table[] = {kPipeZero,        kPipeOne,           kPipeSrcColor,   kPipeInvSrcColor,
                                kPipeDstColor,    kPipeInvDstColor,   kPipeSrcAlpha,   kPipeInvSrcAlpha,
                                kPipeDstAlpha,    kPipeInvDstAlpha,   kPipeConstColor, kPipeInvConstColor,
                                kPipeConstAlpha,  kPipeInvConstAlpha, kPipeSrcAlphaSaturate};
  return table[size_t(f)];
}

// lp_build_blend_factor_complementary: the destination factor is the source's inverse.
constexpr bool pipeComplementary(unsigned src, unsigned dst) { return dst == (src ^ 0x10u); }

}  // namespace oitref::detail
