// Texture sampling (include/oitref/core/texture.h): GL 4.6 §8.14.1–8.14.3 and §8.15 in their words'
// order, in double, rounded to fp32 once at the end (the `exact` reading).
#include <algorithm>
#include <cmath>

#include "oitref/core/texture.h"
#include "texture/level_plan.h"

namespace oitref {
namespace {

using detail::LevelPlan;
using detail::textureCoordinate;
using detail::wrap;

// §8.14.2: NEAREST reads texel (wrap(⌊u⌋), wrap(⌊v⌋)), u = s·w_t, v = t·h_t of the level.
glm::dvec4 nearest(const Texture2D& tex, const SamplerState& sp, int level, double s, double t) {
  const TextureLevel& l = tex.level(level);
  const double u = textureCoordinate(s * l.width), v = textureCoordinate(t * l.height);
  return tex.texel(level, wrap(sp.wrapS, int(std::floor(u)), l.width), wrap(sp.wrapT, int(std::floor(v)), l.height));
}

// §8.14.2: LINEAR weighs the 2×2 texels around (u − ½, v − ½) by α = frac(u − ½),
// β = frac(v − ½); the second column and row are wrap(⌊u − ½⌋ + 1), wrap(⌊v − ½⌋ + 1).
glm::dvec4 linear(const Texture2D& tex, const SamplerState& sp, int level, double s, double t) {
  const TextureLevel& l = tex.level(level);
  const double u = textureCoordinate(s * l.width) - 0.5, v = textureCoordinate(t * l.height) - 0.5;
  const double fu = std::floor(u), fv = std::floor(v);
  const double a = u - fu, b = v - fv;
  const int i0 = wrap(sp.wrapS, int(fu), l.width), i1 = wrap(sp.wrapS, int(fu) + 1, l.width);
  const int j0 = wrap(sp.wrapT, int(fv), l.height), j1 = wrap(sp.wrapT, int(fv) + 1, l.height);
  return (1.0 - a) * (1.0 - b) * tex.texel(level, i0, j0) + a * (1.0 - b) * tex.texel(level, i1, j0) +
         (1.0 - a) * b * tex.texel(level, i0, j1) + a * b * tex.texel(level, i1, j1);
}

glm::dvec4 filterLevel(const Texture2D& tex, const SamplerState& sp, bool linearWithin, int level, double s, double t) {
  return linearWithin ? linear(tex, sp, level, s, t) : nearest(tex, sp, level, s, t);
}

bool usesMipmaps(TextureFilter f) { return f != TextureFilter::Nearest && f != TextureFilter::Linear; }

}  // namespace

glm::vec4 sampleTexture(const Texture2D& tex, const SamplerState& sp, float sIn, float tIn, double lodBase,
                        TextureFiltering rule, bool explicitLod) {
  const double s = sIn, t = tIn;
  // §8.17: a mipmap minification filter needs every level down to 1×1 (q + 1 of them), else the
  // texture is incomplete, and an incomplete texture reads as (0, 0, 0, 1) (§11.1.3.5).
  const TextureLevel& base = tex.level(0);
  const int q = lastMipmapLevel(base.width, base.height);
  if (usesMipmaps(sp.minFilter) && tex.levels() < q + 1) return glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  // §8.14.1: λ' = λ_base + bias, then clamped to [min_lod, max_lod] (a NaN λ_base: min_lod).
  const double biased = lodBase + double(sp.lodBias);
  double lambda = biased > sp.maxLod ? sp.maxLod : biased >= sp.minLod ? biased : double(sp.minLod);
  // The H200 holds λ with 8 fractional bits, truncated, before it decides magnification and
  // levels (magnification up to λ < 1/256; docs/nvidia.md, "Texture sampling").
  const bool nvidia = rule == TextureFiltering::Nvidia;
  if (nvidia) lambda = std::floor(lambda * 256.0) / 256.0;
  // Which levels, filtered how, and the second level's weight (§8.14, §8.14.3, §8.15).
  LevelPlan plan;
  if (lambda <= 0.0) {  // §8.14: magnified; §8.15: the mag filter on level_base
    plan.linearWithin = sp.magFilter == TextureFilter::Linear;
  } else {
    const TextureFilter f = sp.minFilter;
    plan.linearWithin = f == TextureFilter::Linear || f == TextureFilter::LinearMipmapNearest ||
                        f == TextureFilter::LinearMipmapLinear;
    if (f == TextureFilter::NearestMipmapNearest || f == TextureFilter::LinearMipmapNearest) {
      // §8.14.3 (level_base 0): d = 0 for λ ≤ ½, ⌈λ + ½⌉ − 1 while λ ≤ q + ½, else q.
      // The H200 rounds a half up instead: level 1 from λ = ½ on.
      plan.d1 = plan.d2 = nvidia ? std::min(q, int(std::floor(lambda + 0.5)))
                          : lambda <= 0.5 ? 0 : lambda <= q + 0.5 ? int(std::ceil(lambda + 0.5)) - 1 : q;
    } else if (f == TextureFilter::NearestMipmapLinear || f == TextureFilter::LinearMipmapLinear) {
      // §8.14.3: d1 = ⌊λ⌋ and d2 = d1 + 1, both q from λ ≥ q on; τ = (1 − frac λ)·τ1 + frac λ·τ2.
      plan.d1 = lambda >= q ? q : int(std::floor(lambda));
      plan.d2 = lambda >= q ? q : plan.d1 + 1;
      plan.fraction = lambda - std::floor(lambda);
      plan.mipLinear = true;
    }
  }
  // The devices' filters (docs/rules.md, "Texture sampling"): the H200's fixed point for both
  // formats; llvmpipe's 8-bit path where Mesa takes it, else its floating-point one.
  if (nvidia) return detail::filterFixedPoint(tex, sp, rule, plan, s, t);
  if (rule == TextureFiltering::Llvmpipe)
    return detail::llvmpipeUsesFixedPoint(tex, sp, explicitLod) ? detail::filterFixedPoint(tex, sp, rule, plan, s, t)
                                                                : detail::filterLlvmpipeFloat(tex, sp, plan, sIn, tIn);
  glm::dvec4 c = filterLevel(tex, sp, plan.linearWithin, plan.d1, s, t);
  if (plan.mipLinear) c = (1.0 - plan.fraction) * c + plan.fraction * filterLevel(tex, sp, plan.linearWithin, plan.d2, s, t);
  return glm::vec4(c);
}

}  // namespace oitref
