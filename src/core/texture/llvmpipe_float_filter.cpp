// llvmpipe's floating-point texture filter (Mesa gallivm, lp_bld_sample_soa.c's general path),
// which it takes where its 8-bit path does not apply (llvmpipeUsesFixedPoint): sRGB textures,
// MIRRORED_REPEAT, and a per-fragment level of detail with unlike minification and magnification
// filters. In fp32 throughout, as Mesa 22.3.6 generates it on a CPU with FMA (LLVM fuses its
// fmuladd); checked against llvmpipe's recorded samples (tests/core/test_fixed_point_filter.cpp):
//  * texel coordinates: u = s·w − ½ (REPEAT on a power-of-two size), fract(s)·w − ½ (REPEAT
//    otherwise), max(min(s·w, w) − ½, 0) (CLAMP_TO_EDGE), each operation rounded to fp32; the
//    texel ⌊u⌋, the weight u − ⌊u⌋; NEAREST reads ⌊s·w⌋;
//  * texels as floats: a UNORM8 byte k is k·fp32(1/255); an sRGB colour byte goes through
//    lp_build_srgb_to_linear (lp_bld_format_srgb.c): k·fp32(1/(12.6·255)) up to k = 15, else
//    the cubic ((0.3012k/255³·k + ...) in Mesa's even/odd Horner form, with FMA);
//  * lerp(w, v0, v1) = fma(w, v1 − v0, v0) (lp_build_lerp), along s, then t, then between levels.
// MIRRORED_REPEAT's coordinates follow GL's table here, not Mesa's float mirror (not measured).
#include <algorithm>
#include <cmath>

#include "texture/level_plan.h"

namespace oitref::detail {
namespace {

// lp_build_srgb_to_linear for a byte k: Mesa's constants are float expressions, stored in double
// and used as fp32; lp_build_polynomial evaluates (x²·c3 + c1)·x + (x²·c2 + c0) with fmuladd.
float llvmpipeSrgbToLinear(int k) {
  const float x = float(k);
  if (x <= 15.0f) return x * (1.0f / (12.6f * 255.0f));
  const float c0 = 0.0023f, c1 = 0.0030f / 255.0f, c2 = 0.6935f / (255.0f * 255.0f),
              c3 = 0.3012f / (255.0f * 255.0f * 255.0f);
  const float x2 = x * x;
  const float odd = std::fma(x2, c3, c1), even = std::fma(x2, c2, c0);
  return std::fma(odd, x, even);
}

float texelFloat(const Texture2D& tex, const TextureLevel& l, int i, int j, int c) {
  const int byte = l.texels[(size_t(j) * size_t(l.width) + size_t(i)) * 4 + size_t(c)];
  if (tex.format() == TextureFormat::Srgb8Alpha8 && c < 3) return llvmpipeSrgbToLinear(byte);
  return llvmpipeUnorm8ToFloat(byte);
}

float lerp(float w, float v0, float v1) { return std::fma(w, v1 - v0, v0); }

// One axis of LINEAR: the two texels and the weight of the second.
struct Axis {
  int c0, c1;
  float weight;
};
Axis linearAxis(WrapMode mode, float s, int size) {
  const float n = float(size);
  float u;
  if (mode == WrapMode::ClampToEdge) {
    u = std::max(std::min(s * n, n) - 0.5f, 0.0f);
  } else if (mode == WrapMode::Repeat && (size & (size - 1)) == 0) {
    u = s * n - 0.5f;
  } else if (mode == WrapMode::Repeat) {
    u = (s - std::floor(s)) * n - 0.5f;
  } else {  // MIRRORED_REPEAT: GL's wrap of the texels (docs/rules.md)
    u = s * n - 0.5f;
  }
  const float f = std::floor(u);
  const int i = int(f);
  return {wrap(mode, i, size), wrap(mode, i + 1, size), u - f};
}

glm::vec4 filterLevel(const Texture2D& tex, const SamplerState& sp, bool linear, int level, float s, float t) {
  const TextureLevel& l = tex.level(level);
  glm::vec4 out;
  if (!linear) {
    const int i = wrap(sp.wrapS, int(std::floor(float(textureCoordinate(s * float(l.width))))), l.width);
    const int j = wrap(sp.wrapT, int(std::floor(float(textureCoordinate(t * float(l.height))))), l.height);
    for (int c = 0; c < 4; ++c) out[c] = texelFloat(tex, l, i, j, c);
    return out;
  }
  const Axis a = linearAxis(sp.wrapS, s, l.width), b = linearAxis(sp.wrapT, t, l.height);
  for (int c = 0; c < 4; ++c) {
    const float top = lerp(a.weight, texelFloat(tex, l, a.c0, b.c0, c), texelFloat(tex, l, a.c1, b.c0, c));
    const float bottom = lerp(a.weight, texelFloat(tex, l, a.c0, b.c1, c), texelFloat(tex, l, a.c1, b.c1, c));
    out[c] = lerp(b.weight, top, bottom);
  }
  return out;
}

}  // namespace

glm::vec4 filterLlvmpipeFloat(const Texture2D& tex, const SamplerState& sp, const LevelPlan& plan, float s, float t) {
  glm::vec4 c = filterLevel(tex, sp, plan.linearWithin, plan.d1, s, t);
  if (!plan.mipLinear) return c;
  const glm::vec4 c2 = filterLevel(tex, sp, plan.linearWithin, plan.d2, s, t);
  const float w = float(plan.fraction);
  for (int k = 0; k < 4; ++k) c[k] = lerp(w, c[k], c2[k]);
  return c;
}

}  // namespace oitref::detail
