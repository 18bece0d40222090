// The GL half of a blend case, in plain data: what a driver stores for a destination written with
// blending off, and for a source then blended onto it. Shared by `oitref glcheck blend` and the
// standalone GPU capture program (oitref-gpu-capture), which must build from EGL/GL headers alone:
// this file knows GL enums and raw bits, nothing of oitref's types.
//
// How a case runs: one texel per case in a texture of the case's format; the destination and the
// source travel as raw fp32 bits (an SSBO read with uintBitsToFloat in the fragment shader), so
// nothing but the format conversion and the blend touches them; each is drawn as a point at its
// texel's centre; cases with equal blend state and constant are drawn together; dither and sRGB
// off; texels read back with glReadPixels in the format's own type.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "glcheck/gl_functions.h"

namespace oitref::glcheck {

struct GlTargetFormat {
  GLenum internalFormat, readFormat, readType;
  int texelBytes;
};

struct GlBlendCase {
  GlTargetFormat format;
  GLenum equationRgb, equationAlpha, srcRgb, dstRgb, srcAlpha, dstAlpha;
  std::array<float, 4> constant;
  std::array<uint32_t, 4> destination, source;  // fp32 bit patterns
};

struct GlTexels {
  std::array<uint8_t, 16> destination{}, result{};
};

// Runs every case on the current context; cases of one internal format share a texture.
// Throws std::runtime_error when GL reports an error or a framebuffer is incomplete.
std::vector<GlTexels> captureBlendCases(const GlFunctions& gl, const std::vector<GlBlendCase>& cases);

}  // namespace oitref::glcheck
