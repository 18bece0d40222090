// GL 4.6 table 17.2, the blend factors, as data used by every blending arithmetic (fp32 in
// blend_math.h, llvmpipe's integers in blend_unorm_integer.cpp).
//
// Every row (f_R, f_G, f_B, f_A) of the table is one of eight candidate vectors v, or 1 − v:
//   0 zero   1 (Rs, Gs, Bs, As)   2 (Rd, Gd, Bd, Ad)   3 (As, As, As, As)   4 (Ad, Ad, Ad, Ad)
//   5 (Rc, Gc, Bc, Ac)   6 (Ac, Ac, Ac, Ac)   7 (f, f, f, 1) with f = min(As, 1 − Ad)
// RGB takes the first three components of its factor's row, alpha the fourth of its own.
#pragma once

#include "oitref/core/blend_state.h"

namespace oitref::detail {

struct FactorRow {
  int row;
  bool oneMinus;
};

constexpr FactorRow factorRow(BlendFactor f) {
  switch (f) {
    case BlendFactor::Zero: return {0, false};
    case BlendFactor::One: return {0, true};
    case BlendFactor::SrcColor: return {1, false};
    case BlendFactor::OneMinusSrcColor: return {1, true};
    case BlendFactor::DstColor: return {2, false};
    case BlendFactor::OneMinusDstColor: return {2, true};
    case BlendFactor::SrcAlpha: return {3, false};
    case BlendFactor::OneMinusSrcAlpha: return {3, true};
    case BlendFactor::DstAlpha: return {4, false};
    case BlendFactor::OneMinusDstAlpha: return {4, true};
    case BlendFactor::ConstantColor: return {5, false};
    case BlendFactor::OneMinusConstantColor: return {5, true};
    case BlendFactor::ConstantAlpha: return {6, false};
    case BlendFactor::OneMinusConstantAlpha: return {6, true};
    case BlendFactor::SrcAlphaSaturate: return {7, false};
  }
  return {0, false};
}

}  // namespace oitref::detail
