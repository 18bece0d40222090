// What a GPU's texture unit computes where GL leaves the precision to the implementation: the
// LINEAR filter's weights, the mipmap interpolation's fraction, the level of detail from implicit
// derivatives, NEAREST's texel addressing near a texel edge, how 2D and trilinear filters combine
// their weights, sRGB decoding and filtering, and where magnification switches to minification
// (issue 20). Each experiment draws a full-screen pass into an RGBA32F target whose pixel i samples
// a small texture at a coordinate computed exactly in fp32 from i (sampling_capture.cpp's shader
// says which), so the value read back shows the GPU's arithmetic.
#pragma once

#include <ostream>

#include "glcheck/gl_functions.h"

namespace oitref::glcheck {

// Writes one CSV line per sample: experiment, index, the exact parameter (the weight, fraction,
// λ or offset that exact arithmetic gives; for bilinear, trilinear, srgb_* and
// magnification_switch the parameter swept) and the red channel read back (decimal and fp32
// bits; srgb_decode's samples from 2048 on: alpha).
void captureSampling(const GlFunctions& gl, std::ostream& csv);

}  // namespace oitref::glcheck
