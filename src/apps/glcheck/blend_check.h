// glcheck's blend mode: each case's destination is written into its own texel with blending off,
// then the source is drawn as a point at that texel's centre with the case's blend state and
// constant. Values reach the fragment shader as raw bits (an SSBO read with uintBitsToFloat), so
// no interpolation or attribute conversion touches them. Texels are read back in the format's own
// type and compared bit for bit with oitref's evaluate() under a profile.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "glcheck/gl_context.h"
#include "tools/blend_case.h"
#include "tools/blend_comparison.h"

namespace oitref::glcheck {

// Runs the cases on the context's driver (gpucapture/blend_capture.h says how). Throws
// std::invalid_argument for a format GL does not have.
std::vector<tools::RecordedTexels> runBlendCases(const GlContext& context, const std::vector<tools::BlendCase>& cases);

}  // namespace oitref::glcheck
