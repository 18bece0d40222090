// What the sampler's rules shared by its filters decide (src/core/texture/sampling.cpp): texel
// coordinates and their wrapping (§8.14.2), and which levels a lookup filters (§8.14.3).
#pragma once

#include "oitref/core/unorm.h"

#include <algorithm>
#include <cmath>

#include "oitref/core/texture.h"

namespace oitref::detail {

// Texel coordinates are integers; beyond ±2^30 they are clamped before wrapping (GL leaves the
// precision of such coordinates to the implementation; a GPU's fixed-point texel addressing has
// far fewer bits), and a NaN coordinate reads as 0.
inline double textureCoordinate(double u) { return std::isnan(u) ? 0.0 : std::clamp(u, -0x1p30, 0x1p30); }

// §8.14.2's wrap table: the wrap of an integer texel coordinate c on a level `size` texels wide.
inline int wrap(WrapMode mode, int c, int size) {
  auto imod = [](int a, int b) {
    const int m = a % b;
    return m < 0 ? m + b : m;
  };
  auto mirror = [](int a) { return a >= 0 ? a : -(1 + a); };
  switch (mode) {
    case WrapMode::Repeat: return imod(c, size);
    case WrapMode::ClampToEdge: return std::clamp(c, 0, size - 1);
    case WrapMode::MirroredRepeat: return (size - 1) - mirror(imod(c, 2 * size) - size);
  }
  return 0;
}

// llvmpipe's conversion of an 8-bit texel value to float (decodeUnorm8Llvmpipe, docs/rules.md, the
// devices' filters). Both of its filter paths (fixed_point_filter.cpp, llvmpipe_float_filter.cpp)
// end in it.
inline float llvmpipeUnorm8ToFloat(int k) { return decodeUnorm8Llvmpipe(uint32_t(k)); }

// A lookup's levels: d1 filtered NEAREST or LINEAR (linearWithin), and for a *_MIPMAP_LINEAR
// filter d2 too, weighted by `fraction` (frac λ).
struct LevelPlan {
  int d1 = 0, d2 = 0;
  bool linearWithin = false, mipLinear = false;
  double fraction = 0.0;
};

// The `llvmpipe` rule's 8-bit filter (UNORM8 textures) and the `nvidia` rule's filter
// (src/core/texture/fixed_point_filter.cpp).
glm::vec4 filterFixedPoint(const Texture2D& tex, const SamplerState& sp, TextureFiltering rule, const LevelPlan& plan,
                           double s, double t);
// Whether llvmpipe filters with its 8-bit AoS path (Mesa lp_bld_sample_soa.c, use_aos): a texture
// that fits 8-bit UNORM (not sRGB), REPEAT or CLAMP_TO_EDGE in s and t, and a level of detail per
// quad (implicit) or minification and magnification filters alike.
bool llvmpipeUsesFixedPoint(const Texture2D& tex, const SamplerState& sp, bool explicitLod);
// llvmpipe's floating-point path otherwise (src/core/texture/llvmpipe_float_filter.cpp).
glm::vec4 filterLlvmpipeFloat(const Texture2D& tex, const SamplerState& sp, const LevelPlan& plan, float s, float t);

}  // namespace oitref::detail
