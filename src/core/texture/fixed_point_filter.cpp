// The texture filters of the `llvmpipe` rule (its 8-bit path, for UNORM8 textures) and the
// `nvidia` rule (UNORM8 and sRGB): texel coordinates in 8.8 fixed point, weights of 8 bits, and
// the filtered value held as an integer of 8 (llvmpipe) or 16 (NVIDIA) bits, or NVIDIA's fp16. Measured with `oitref-gpu-capture sampling`
// (docs/nvidia.md, "Texture sampling"; tests/data/sampling_*.csv.gz); llvmpipe's lerp is that of
// Mesa's gallivm (lp_bld_arit.c, lp_build_lerp_simple: pmulhrsw of the weight and the difference
// shifted left by 7, i.e. ⌊(w·Δ + 128)/256⌋; lp_build_lerp_2d: along s, then along t).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "oitref/core/fp16.h"
#include "texture/level_plan.h"
#include "texture/nvidia_srgb_table.h"

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

// x/256 rounded to the nearest integer, ties to even.
int64_t roundEven256(int64_t x) {
  const int64_t q = x >> 8, r = x & 255;
  return q + int64_t(r > 128 || (r == 128 && (q & 1)));
}

// A non-negative x rounded to fp16's grid, ties up (away from zero).
float roundHalfUpToHalf(double x) {
  if (x == 0.0) return 0.0f;
  int e = 0;
  std::frexp(x, &e);                                  // x in [2^(e−1), 2^e)
  const double ulp = std::ldexp(1.0, std::max(e - 1, -14) - 10);  // fp16's spacing there
  return float(std::floor(x / ulp + 0.5) * ulp);
}

// The H200: each texel's weight from the 8-bit s weight and the level's weight λw (256, or
// 256 − w and w for *_MIPMAP_LINEAR), rounded, then the t weight, rounded — R(R(wa·λw)·wb),
// ties to even (fits every bilinear sample and 4,023 of 4,096 trilinear ones); the weighted
// texels of both levels summed at once: UNORM8 bytes widened to 16 bits (k·257), the sum rounded
// to 16 bits half up; an sRGB texture's colour bytes read through the recorded decode table and
// the sum rounded to fp16, ties up (4,081 of 4,096 samples between adjacent codes).
void addNvidiaLevel(const Texture2D& tex, const TextureLevel& l, const Footprint& f, int levelWeight, int64_t unorm[4],
                    double half[4]) {
  const int64_t wa[2] = {256 - f.a, f.a}, wb[2] = {256 - f.b, f.b};
  const int is[2] = {f.i0, f.i1}, js[2] = {f.j0, f.j1};
  const bool srgb = tex.format() == TextureFormat::Srgb8Alpha8;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      const int64_t q = roundEven256(roundEven256(wa[x] * levelWeight) * wb[y]);
      for (int c = 0; c < 4; ++c) {
        const int byte = texelByte(l, is[x], js[y], c);
        if (srgb && c < 3) half[c] += double(q) * double(decodeHalf(kNvidiaSrgbDecodeHalf[byte]));
        else unorm[c] += q * 257 * byte;
      }
    }
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
  if (rule == TextureFiltering::Llvmpipe) {
    for (int c = 0; c < 4; ++c) {
      int v = llvmpipeLevel(l1, f1, c);
      if (plan.mipLinear) v = lerp8(v, llvmpipeLevel(l2, f2, c), w);
      out[c] = llvmpipeUnorm8ToFloat(v);
    }
    return out;
  }
  int64_t unorm[4] = {};
  double half[4] = {};
  addNvidiaLevel(tex, l1, f1, plan.mipLinear ? 256 - w : 256, unorm, half);
  if (plan.mipLinear) addNvidiaLevel(tex, l2, f2, w, unorm, half);
  const bool srgb = tex.format() == TextureFormat::Srgb8Alpha8;
  for (int c = 0; c < 4; ++c)
    out[c] = srgb && c < 3 ? roundHalfUpToHalf(half[c] / 256.0) : float(double((unorm[c] + 128) >> 8) / 65535.0);
  return out;
}

bool llvmpipeUsesFixedPoint(const Texture2D& tex, const SamplerState& sp, bool explicitLod) {
  auto simple = [](WrapMode m) { return m == WrapMode::Repeat || m == WrapMode::ClampToEdge; };
  auto linear = [](TextureFilter f) {
    return f == TextureFilter::Linear || f == TextureFilter::LinearMipmapNearest || f == TextureFilter::LinearMipmapLinear;
  };
  return tex.format() == TextureFormat::Rgba8 && simple(sp.wrapS) && simple(sp.wrapT) &&
         (!explicitLod || linear(sp.minFilter) == linear(sp.magFilter));
}

}  // namespace oitref::detail
