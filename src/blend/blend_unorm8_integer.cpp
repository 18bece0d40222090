#include "blend/blend_unorm8_integer.h"

#include "blend/blend_factor.h"

namespace oitref::detail {
namespace {

uint32_t equation8(BlendEquation eq, uint32_t s, uint32_t d, uint32_t sf, uint32_t df) {
  const int a = int(mulUnorm8(s, sf)), b = int(mulUnorm8(d, df));
  int r = 0;
  switch (eq) {
    case BlendEquation::Add: r = a + b; break;
    case BlendEquation::Subtract: r = a - b; break;
    case BlendEquation::ReverseSubtract: r = b - a; break;
    case BlendEquation::Min: return s < d ? s : d;
    case BlendEquation::Max: return s > d ? s : d;
  }
  return uint32_t(r < 0 ? 0 : r > 255 ? 255 : r);
}

}  // namespace

void blendUnorm8Integer(int channels, const BlendState& state, const glm::vec4& constant, UnormRounding rounding,
                        const glm::vec4& source, unsigned writeMask, uint8_t* texel) {
  uint32_t s[4], d[4] = {0, 0, 0, 255}, c[4];
  for (int ch = 0; ch < 4; ++ch) {
    s[ch] = encodeUnorm(source[ch], 8, rounding);
    c[ch] = encodeUnorm(constant[ch], 8, rounding);
  }
  for (int ch = 0; ch < channels; ++ch) d[ch] = texel[ch];
  const uint32_t ad = channels == 4 ? d[3] : 255;
  for (int ch = 0; ch < channels; ++ch) {
    if (!(writeMask & (1u << ch))) continue;
    const bool alpha = ch == 3;
    const uint32_t sf = blendFactorRow(alpha ? state.srcAlpha : state.srcRgb, s, d, ad, c, 255u)[size_t(ch)];
    const uint32_t df = blendFactorRow(alpha ? state.dstAlpha : state.dstRgb, s, d, ad, c, 255u)[size_t(ch)];
    texel[ch] = uint8_t(equation8(alpha ? state.equationAlpha : state.equationRgb, s[ch], d[ch], sf, df));
  }
}

}  // namespace oitref::detail
