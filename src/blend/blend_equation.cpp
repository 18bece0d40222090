// GL 4.6 §17.3.6 blending in fp32; see include/oitref/blend.h for every rule implemented here.
#include <cmath>
#include <limits>

#include "blend/blend_factor.h"
#include "blend/blend_unorm8_integer.h"
#include "oitref/blend.h"
#include "oitref/unorm.h"

namespace oitref {
namespace {

// IEEE minNum/maxNum; on equality the source (first operand).
float minNum(float s, float d) {
  if (std::isnan(s)) return d;
  if (std::isnan(d)) return s;
  return d < s ? d : s;
}
float maxNum(float s, float d) {
  if (std::isnan(s)) return d;
  if (std::isnan(d)) return s;
  return d > s ? d : s;
}

// Table 17.1, each product rounded to fp32 before the sum.
float blendEquation(BlendEquation eq, float s, float d, float sf, float df) {
  switch (eq) {
    case BlendEquation::Add: { const float a = s * sf, b = d * df; return a + b; }
    case BlendEquation::Subtract: { const float a = s * sf, b = d * df; return a - b; }
    case BlendEquation::ReverseSubtract: { const float a = s * sf, b = d * df; return b - a; }
    case BlendEquation::Min: return minNum(s, d);
    case BlendEquation::Max: return maxNum(s, d);
  }
  return 0.0f;
}

glm::vec4 clampUnit4(const glm::vec4& v) {
  return {clampUnit(v[0]), clampUnit(v[1]), clampUnit(v[2]), clampUnit(v[3])};
}

bool isUnorm8(const Format& f) {
  return f.id == FormatId::R8 || f.id == FormatId::RG8 || f.id == FormatId::RGBA8;
}

// NaN sign and payload from arithmetic differ between CPUs (x86's default NaN is negative,
// ARM's positive) and GL does not specify them: blend results that are NaN are canonical.
const float kCanonicalNan = std::numeric_limits<float>::quiet_NaN();

}  // namespace

glm::vec4 blendFloat(const BlendState& state, const glm::vec4& source, const glm::vec4& destination,
                     const glm::vec4& constant, bool fixedPoint, bool targetHasAlpha) {
  const glm::vec4 s = fixedPoint ? clampUnit4(source) : source;
  const glm::vec4 d = fixedPoint ? clampUnit4(destination) : destination;
  const glm::vec4 c = fixedPoint ? clampUnit4(constant) : constant;
  const float ad = targetHasAlpha ? d[3] : 1.0f;
  glm::vec4 result;
  for (int ch = 0; ch < 4; ++ch) {
    const bool alpha = ch == 3;
    const BlendEquation eq = alpha ? state.equationAlpha : state.equationRgb;
    const float sf = detail::selectBlendFactor(alpha ? state.srcAlpha : state.srcRgb, ch, s, d, ad, c, 1.0f);
    const float df = detail::selectBlendFactor(alpha ? state.dstAlpha : state.dstRgb, ch, s, d, ad, c, 1.0f);
    const float r = blendEquation(eq, s[ch], d[ch], sf, df);
    result[ch] = std::isnan(r) ? kCanonicalNan : r;
  }
  return fixedPoint ? clampUnit4(result) : result;
}

void blendIntoTexel(const Format& format, const BlendState& state, const glm::vec4& constant,
                    const Profile& profile, const glm::vec4& source, uint8_t* texel) {
  const unsigned allChannels = (1u << format.channels) - 1;
  const unsigned mask = state.writeMask & allChannels;
  if (mask == 0) return;
  if (state.enabled && profile.unorm8Blend == Unorm8Blend::Integer && isUnorm8(format)) {
    detail::blendUnorm8Integer(format.channels, state, constant, profile.unorm, source, mask, texel);
    return;
  }
  const glm::vec4 result =
      state.enabled ? blendFloat(state, source, decodeTexel(format, texel), constant, format.isUnorm(), format.hasAlpha())
                    : source;
  if (mask == allChannels) {
    encodeTexel(format, result, profile, texel);
    return;
  }
  uint8_t encoded[16];
  encodeTexel(format, result, profile, encoded);
  mergeTexelChannels(format, encoded, texel, mask);
}

}  // namespace oitref
