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

namespace oitref::glcheck {

struct GlTexels {
  std::array<uint8_t, 16> destination{}, result{};
};

// One texture per format, one draw per run of cases that share blend state and constant.
// Throws std::invalid_argument for a format GL does not have.
std::vector<GlTexels> runBlendCases(const GlContext& context, const std::vector<tools::BlendCase>& cases);

struct BlendCheckSummary {
  size_t cases = 0, destinationMismatches = 0, resultMismatches = 0;
};

// Compares GL's texels with oitref's and prints, per format, per equation and per factor, the
// share of bit-equal stored destinations and results, then the first `listMismatches`
// mismatches with both bit patterns. `lineNumbers[i]` names case i in reports (CSV line).
BlendCheckSummary compareBlendCases(const std::vector<tools::BlendCase>& cases, const std::vector<GlTexels>& gl,
                                    const Profile& profile, const std::vector<size_t>& lineNumbers,
                                    size_t listMismatches, std::ostream& out);

}  // namespace oitref::glcheck
