// GL 4.6 table 17.2, the blend factors, written once for every arithmetic that blends:
// fp32 (T = float, one = 1) and llvmpipe's 8-bit integers (T = uint32_t, one = 255).
// `ch` 0..2 are R, G, B; 3 is alpha, where the colour factors use the alpha component.
// `ad` is the destination alpha as read (1 for targets without alpha, §17.3.6.6).
#pragma once

#include "oitref/blend_state.h"

namespace oitref::detail {

template <typename T, typename Vec>
T selectBlendFactor(BlendFactor f, int ch, const Vec& s, const Vec& d, T ad, const Vec& c, T one) {
  const T dc = ch == 3 ? ad : T(d[ch]);
  switch (f) {
    case BlendFactor::Zero: return T(0);
    case BlendFactor::One: return one;
    case BlendFactor::SrcColor: return s[ch];
    case BlendFactor::OneMinusSrcColor: return one - s[ch];
    case BlendFactor::DstColor: return dc;
    case BlendFactor::OneMinusDstColor: return one - dc;
    case BlendFactor::SrcAlpha: return s[3];
    case BlendFactor::OneMinusSrcAlpha: return one - s[3];
    case BlendFactor::DstAlpha: return ad;
    case BlendFactor::OneMinusDstAlpha: return one - ad;
    case BlendFactor::ConstantColor: return c[ch];
    case BlendFactor::OneMinusConstantColor: return one - c[ch];
    case BlendFactor::ConstantAlpha: return c[3];
    case BlendFactor::OneMinusConstantAlpha: return one - c[3];
    case BlendFactor::SrcAlphaSaturate: {  // min(As, 1 − Ad) for RGB, 1 for alpha
      if (ch == 3) return one;
      const T oneMinusAd = one - ad;
      return s[3] < oneMinusAd ? T(s[3]) : oneMinusAd;
    }
  }
  return T(0);
}

}  // namespace oitref::detail
