// The texture filters of the `llvmpipe` and `nvidia` rules (TextureFiltering), for UNORM8
// textures: texel coordinates in 8.8 fixed point, weights of 8 bits, and the filtered value held
// as an integer of 8 (llvmpipe) or 16 (NVIDIA) bits. Measured with `oitref-gpu-capture sampling`
// (docs/nvidia.md, "Texture sampling"; tests/data/sampling_*.csv.gz); llvmpipe's lerp is that of
// Mesa's gallivm (lp_bld_arit.c, lp_build_lerp_simple: pmulhrsw of the weight and the difference
// shifted left by 7, i.e. ⌊(w·Δ + 128)/256⌋; lp_build_lerp_2d: along s, then along t).
#include <cmath>
#include <cstdint>

#include "texture/level_plan.h"

namespace oitref::detail {
namespace {

// A level's 8.8 fixed-point texel coordinate of LINEAR, u·256 − 128, rounded as the device
// rounds it: llvmpipe converts with the CPU's round-to-nearest-even, the GPU rounds half up.
int64_t fixedPointCoordinate(TextureFiltering rule, double u) {
  const double x = textureCoordinate(u) * 256.0 - 128.0;
  return rule == TextureFiltering::Llvmpipe ? int64_t(std::nearbyint(x)) : int64_t(std::floor(x + 0.5));
}

// The texels a lookup reads on one level and their weights: four texels (i0/i1 × j0/j1) with
// 8-bit weights a, b (of texel i1, j1) for LINEAR; one texel (weights 0) for NEAREST.
struct Footprint {
  int i0, i1, j0, j1;
  int a, b;  // 0..255, in 256ths
};

Footprint footprint(const TextureLevel& l, const SamplerState& sp, TextureFiltering rule, bool linear, double s, double t) {
  Footprint f{};
  if (!linear) {  // NEAREST: ⌊u⌋, as the exact rule (both devices agreed with it to 2^-20 of a texel)
    f.i0 = f.i1 = wrap(sp.wrapS, int(std::floor(textureCoordinate(s * l.width))), l.width);
    f.j0 = f.j1 = wrap(sp.wrapT, int(std::floor(textureCoordinate(t * l.height))), l.height);
    return f;
  }
  const int64_t u = fixedPointCoordinate(rule, s * l.width), v = fixedPointCoordinate(rule, t * l.height);
  const int iu = int(u >> 8), iv = int(v >> 8);  // arithmetic shift: ⌊·/256⌋
  f.a = int(u & 255), f.b = int(v & 255);
  f.i0 = wrap(sp.wrapS, iu, l.width), f.i1 = wrap(sp.wrapS, iu + 1, l.width);
  f.j0 = wrap(sp.wrapT, iv, l.height), f.j1 = wrap(sp.wrapT, iv + 1, l.height);
  return f;
}

int texelByte(const TextureLevel& l, int i, int j, int channel) {
  return l.texels[(size_t(j) * size_t(l.width) + size_t(i)) * 4 + size_t(channel)];
}

// llvmpipe's 8-bit lerp: v0 + ⌊(w·(v1 − v0) + 128) / 256⌋.
int lerp8(int v0, int v1, int w) { return v0 + ((w * (v1 - v0) + 128) >> 8); }

int llvmpipeLevel(const TextureLevel& l, const Footprint& f, int c) {
  const int top = lerp8(texelByte(l, f.i0, f.j0, c), texelByte(l, f.i1, f.j0, c), f.a);
  const int bottom = lerp8(texelByte(l, f.i0, f.j1, c), texelByte(l, f.i1, f.j1, c), f.a);
  return lerp8(top, bottom, f.b);
}

// NVIDIA: Σ weight·texel with texels widened to 16 bits (k·257) and the 8-bit weights' exact
// products, in units of 2^-16 of a 16-bit step per level.
int64_t nvidiaLevel(const TextureLevel& l, const Footprint& f, int c) {
  const int64_t wa[2] = {256 - f.a, f.a}, wb[2] = {256 - f.b, f.b};
  const int is[2] = {f.i0, f.i1}, js[2] = {f.j0, f.j1};
  int64_t sum = 0;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) sum += wa[x] * wb[y] * 257 * texelByte(l, is[x], js[y], c);
  return sum;
}

}  // namespace

glm::vec4 filterFixedPoint(const Texture2D& tex, const SamplerState& sp, TextureFiltering rule, const LevelPlan& plan,
                           double s, double t) {
  const TextureLevel& l1 = tex.level(plan.d1);
  const TextureLevel& l2 = tex.level(plan.d2);
  const Footprint f1 = footprint(l1, sp, rule, plan.linearWithin, s, t);
  const Footprint f2 = footprint(l2, sp, rule, plan.linearWithin, s, t);
  // Both devices truncate the level fraction to 8 bits.
  const int w = plan.mipLinear ? int(std::floor(plan.fraction * 256.0)) : 0;
  glm::vec4 out;
  for (int c = 0; c < 4; ++c) {
    if (rule == TextureFiltering::Llvmpipe) {
      int v = llvmpipeLevel(l1, f1, c);
      if (plan.mipLinear) v = lerp8(v, llvmpipeLevel(l2, f2, c), w);
      out[c] = float(v) * (1.0f / 255.0f);  // llvmpipe's conversion: one fp32 multiply
    } else {
      // One rounding of the whole weighted sum to 16 bits, half up (measured on one axis and on
      // the level fraction; the order of a 2D or trilinear sum is an assumption).
      int64_t sum = nvidiaLevel(l1, f1, c) * (plan.mipLinear ? 256 - w : 256);
      if (plan.mipLinear) sum += nvidiaLevel(l2, f2, c) * w;
      const int64_t v16 = (sum + (int64_t(1) << 23)) >> 24;
      out[c] = float(double(v16) / 65535.0);
    }
  }
  return out;
}

}  // namespace oitref::detail
