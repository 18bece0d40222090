#include "blend/blend_unorm8_integer.h"

#include "blend/blend_factor.h"

namespace oitref::detail {
namespace {

// Channel ch of a factor: candidate row of blend_factor.h in 8-bit integers, 1 − v as 255 − v.
uint32_t factor8(BlendFactor f, int ch, const uint32_t s[4], const uint32_t d[4], uint32_t ad, const uint32_t c[4]) {
  const FactorRow fr = factorRow(f);
  uint32_t v = 0;
  switch (fr.row) {
    case 0: v = 0; break;
    case 1: v = s[ch]; break;
    case 2: v = ch == 3 ? ad : d[ch]; break;
    case 3: v = s[3]; break;
    case 4: v = ad; break;
    case 5: v = c[ch]; break;
    case 6: v = c[3]; break;
    case 7: v = ch == 3 ? 255 : (s[3] < 255 - ad ? s[3] : 255 - ad); break;
  }
  return fr.oneMinus ? 255 - v : v;
}

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
    const uint32_t sf = factor8(alpha ? state.srcAlpha : state.srcRgb, ch, s, d, ad, c);
    const uint32_t df = factor8(alpha ? state.dstAlpha : state.dstRgb, ch, s, d, ad, c);
    texel[ch] = uint8_t(equation8(alpha ? state.equationAlpha : state.equationRgb, s[ch], d[ch], sf, df));
  }
}

}  // namespace oitref::detail
