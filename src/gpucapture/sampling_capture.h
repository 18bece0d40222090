// What a GPU's texture unit computes where GL leaves the precision to the implementation: the
// LINEAR filter's weights, the mipmap interpolation's fraction, the level of detail from implicit
// derivatives, and NEAREST's texel addressing near a texel edge (issue 20). Each experiment draws
// a full-screen pass into an RGBA32F target whose pixel i samples a texture of 0 and 255 texels at
// a coordinate computed exactly in fp32 from i, so the value read back is the GPU's weight itself.
#pragma once

#include <ostream>

#include "glcheck/gl_functions.h"

namespace oitref::glcheck {

// Writes one CSV line per sample: experiment, index, the exact parameter (the weight, fraction,
// λ or offset that exact arithmetic gives), and the red channel read back (decimal and fp32 bits).
void captureSampling(const GlFunctions& gl, std::ostream& csv);

}  // namespace oitref::glcheck
