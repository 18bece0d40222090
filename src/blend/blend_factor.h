// GL 4.6 table 17.2, the blend factors, written once for every arithmetic that blends:
// fp32 (T = float, one = 1) and llvmpipe's 8-bit integers (T = uint32_t, one = 255).
// Each factor is the table's row (f_R, f_G, f_B, f_A); RGB takes the first three components of
// its factor's row and alpha the fourth of its own. `ad` is the destination alpha as read (1 for
// targets without alpha, §17.3.6.6).
#pragma once

#include <array>

#include "oitref/blend_state.h"

namespace oitref::detail {

template <typename T, typename Vec>
inline std::array<T, 4> blendFactorRow(BlendFactor f, const Vec& s, const Vec& d, T ad, const Vec& c, T one) {
  switch (f) {
    case BlendFactor::Zero: return {T(0), T(0), T(0), T(0)};
    case BlendFactor::One: return {one, one, one, one};
    case BlendFactor::SrcColor: return {T(s[0]), T(s[1]), T(s[2]), T(s[3])};
    case BlendFactor::OneMinusSrcColor: return {T(one - s[0]), T(one - s[1]), T(one - s[2]), T(one - s[3])};
    case BlendFactor::DstColor: return {T(d[0]), T(d[1]), T(d[2]), ad};
    case BlendFactor::OneMinusDstColor: return {T(one - d[0]), T(one - d[1]), T(one - d[2]), T(one - ad)};
    case BlendFactor::SrcAlpha: return {T(s[3]), T(s[3]), T(s[3]), T(s[3])};
    case BlendFactor::OneMinusSrcAlpha: { const T v = one - s[3]; return {v, v, v, v}; }
    case BlendFactor::DstAlpha: return {ad, ad, ad, ad};
    case BlendFactor::OneMinusDstAlpha: { const T v = one - ad; return {v, v, v, v}; }
    case BlendFactor::ConstantColor: return {T(c[0]), T(c[1]), T(c[2]), T(c[3])};
    case BlendFactor::OneMinusConstantColor: return {T(one - c[0]), T(one - c[1]), T(one - c[2]), T(one - c[3])};
    case BlendFactor::ConstantAlpha: return {T(c[3]), T(c[3]), T(c[3]), T(c[3])};
    case BlendFactor::OneMinusConstantAlpha: { const T v = one - c[3]; return {v, v, v, v}; }
    case BlendFactor::SrcAlphaSaturate: {  // (f, f, f, 1) with f = min(As, 1 − Ad)
      const T oneMinusAd = one - ad;
      const T f3 = T(s[3]) < oneMinusAd ? T(s[3]) : oneMinusAd;
      return {f3, f3, f3, one};
    }
  }
  return {T(0), T(0), T(0), T(0)};
}

}  // namespace oitref::detail
