// Texture sampling (include/oitref/texture.h): GL 4.6 §8.14.1–8.14.3 and §8.15 in their words'
// order, in double, rounded to fp32 once at the end (the `exact` reading).
#include <algorithm>
#include <cmath>

#include "oitref/texture.h"

namespace oitref {
namespace {

// Texel coordinates are integers; beyond ±2^30 they are clamped before wrapping (GL leaves the
// precision of such coordinates to the implementation; a GPU's fixed-point texel addressing has
// far fewer bits), and a NaN coordinate reads as 0.
double textureCoordinate(double u) { return std::isnan(u) ? 0.0 : std::clamp(u, -0x1p30, 0x1p30); }

int imod(int a, int b) {
  const int m = a % b;
  return m < 0 ? m + b : m;
}
int mirror(int a) { return a >= 0 ? a : -(1 + a); }

// §8.14.2's wrap table: the wrap of an integer texel coordinate c on a level `size` texels wide.
int wrap(WrapMode mode, int c, int size) {
  switch (mode) {
    case WrapMode::Repeat: return imod(c, size);
    case WrapMode::ClampToEdge: return std::clamp(c, 0, size - 1);
    case WrapMode::MirroredRepeat: return (size - 1) - mirror(imod(c, 2 * size) - size);
  }
  return 0;
}

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

glm::vec4 sampleTexture(const Texture2D& tex, const SamplerState& sp, float sIn, float tIn, double lodBase) {
  const double s = sIn, t = tIn;
  // §8.17: a mipmap minification filter needs every level down to 1×1 (q + 1 of them), else the
  // texture is incomplete, and an incomplete texture reads as (0, 0, 0, 1) (§11.1.3.5).
  const TextureLevel& base = tex.level(0);
  const int q = lastMipmapLevel(base.width, base.height);
  if (usesMipmaps(sp.minFilter) && tex.levels() < q + 1) return glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  // §8.14.1: λ' = λ_base + bias, then clamped to [min_lod, max_lod] (a NaN λ_base: min_lod).
  const double biased = lodBase + double(sp.lodBias);
  const double lambda = biased > sp.maxLod ? sp.maxLod : biased >= sp.minLod ? biased : double(sp.minLod);
  glm::dvec4 c;
  if (lambda <= 0.0) {  // §8.14: magnified; §8.15: the mag filter on level_base
    c = filterLevel(tex, sp, sp.magFilter == TextureFilter::Linear, 0, s, t);
  } else {
    const TextureFilter f = sp.minFilter;
    const bool within = f == TextureFilter::Linear || f == TextureFilter::LinearMipmapNearest ||
                        f == TextureFilter::LinearMipmapLinear;
    if (!usesMipmaps(f)) {
      c = filterLevel(tex, sp, within, 0, s, t);
    } else if (f == TextureFilter::NearestMipmapNearest || f == TextureFilter::LinearMipmapNearest) {
      // §8.14.3 (level_base 0): d = 0 for λ ≤ ½, ⌈λ + ½⌉ − 1 while λ ≤ q + ½, else q.
      const int d = lambda <= 0.5 ? 0 : lambda <= q + 0.5 ? int(std::ceil(lambda + 0.5)) - 1 : q;
      c = filterLevel(tex, sp, within, d, s, t);
    } else {
      // §8.14.3: d1 = ⌊λ⌋ and d2 = d1 + 1, both q from λ ≥ q on; τ = (1 − frac λ)·τ1 + frac λ·τ2.
      const int d1 = lambda >= q ? q : int(std::floor(lambda));
      const int d2 = lambda >= q ? q : d1 + 1;
      const double f2 = lambda - std::floor(lambda);
      c = (1.0 - f2) * filterLevel(tex, sp, within, d1, s, t) + f2 * filterLevel(tex, sp, within, d2, s, t);
    }
  }
  return glm::vec4(c);
}

}  // namespace oitref
