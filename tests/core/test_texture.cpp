// Texture sampling against values derived here from GL 4.6 §8.14–8.17 by hand or by independent
// arithmetic: bilinear filtering reproduces a linear ramp exactly, wrap modes read the texels the
// spec's tables name, the level of detail picks the levels §8.14.3 gives, an incomplete
// texture reads (0, 0, 0, 1), and the box filter rounds like integer arithmetic does.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include "oitref/core/texture.h"

namespace oitref::test {
namespace {

// A texture whose red channel at texel (i, j) is r(i, j); green 0, blue 0, alpha 255.
Texture2D textureOf(int w, int h, int (*r)(int, int), TextureFormat format = TextureFormat::Rgba8) {
  std::vector<uint8_t> bytes(size_t(w) * size_t(h) * 4);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      uint8_t* p = &bytes[(size_t(j) * size_t(w) + size_t(i)) * 4];
      p[0] = uint8_t(r(i, j)), p[1] = 0, p[2] = 0, p[3] = 255;
    }
  return Texture2D(format, w, h, std::move(bytes));
}
TextureLevel constantLevel(int w, int h, uint8_t red) {
  TextureLevel l{w, h, std::vector<uint8_t>(size_t(w) * size_t(h) * 4, 0)};
  for (size_t k = 0; k < l.texels.size(); k += 4) l.texels[k] = red, l.texels[k + 3] = 255;
  return l;
}

SamplerState samplerWith(TextureFilter min, TextureFilter mag, WrapMode wrap = WrapMode::ClampToEdge) {
  SamplerState s;
  s.minFilter = min, s.magFilter = mag, s.wrapS = s.wrapT = wrap;
  return s;
}

}  // namespace

TEST_CASE("texture: LINEAR reproduces a linear ramp exactly between texel centres", "[texture]") {
  // r(i, j) = 10 + 7i + 5j at texel centres (i + ½, j + ½): bilinear weights reproduce any
  // function linear in u and v, so at (u, v) the value is 10 + 7(u − ½) + 5(v − ½), over 255.
  const Texture2D tex = textureOf(16, 8, [](int i, int j) { return 10 + 7 * i + 5 * j; });
  const SamplerState sp = samplerWith(TextureFilter::Linear, TextureFilter::Linear);
  for (float s = 0.5f / 16; s <= 15.5f / 16; s += 0.013f)
    for (float t = 0.5f / 8; t <= 7.5f / 8; t += 0.029f) {
      const double u = double(s) * 16, v = double(t) * 8;
      const double want = (10.0 + 7.0 * (u - 0.5) + 5.0 * (v - 0.5)) / 255.0;
      const glm::vec4 got = sampleTexture(tex, sp, s, t, -1.0);
      REQUIRE(std::abs(double(got.r) - want) <= 1e-6 * want);
      REQUIRE(got.a == 1.0f);
    }
}

TEST_CASE("texture: NEAREST reads the texels the wrap modes' table names", "[texture]") {
  // r = 10·i on a 4-texel row; u = 4s at s = (c + ½)/4 lies in integer texel coordinate c.
  const Texture2D tex = textureOf(4, 1, [](int i, int) { return 10 * i; });
  // Texel coordinate c → texel, read off each mode's definition: repeat is periodic in 4, clamp
  // stops at the edges, mirrored repeat runs 0 1 2 3 3 2 1 0 and then again.
  const int coords[] = {-5, -4, -3, -2, -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const int repeat[] = {3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1};
  const int clamp[] = {0, 0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3, 3};
  const int mirrored[] = {3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0, 1};
  for (size_t k = 0; k < std::size(coords); ++k) {
    const float s = (float(coords[k]) + 0.5f) / 4.0f;
    INFO("texel coordinate " << coords[k]);
    const auto at = [&](WrapMode m) {
      return sampleTexture(tex, samplerWith(TextureFilter::Nearest, TextureFilter::Nearest, m), s, 0.5f, -1.0).r;
    };
    CHECK(at(WrapMode::Repeat) == float(10 * repeat[k] / 255.0));
    CHECK(at(WrapMode::ClampToEdge) == float(10 * clamp[k] / 255.0));
    CHECK(at(WrapMode::MirroredRepeat) == float(10 * mirrored[k] / 255.0));
  }
}

TEST_CASE("texture: LINEAR across a wrapped edge weighs the wrapped neighbour", "[texture]") {
  const Texture2D tex = textureOf(4, 1, [](int i, int) { return 10 * i; });
  // s = 0.05: u − ½ = −0.3, so texel coordinates −1 and 0 with weights 0.3 and 0.7.
  const float s = 0.05f;
  const double a = double(s) * 4 - 0.5 - std::floor(double(s) * 4 - 0.5);  // 0.7, in double as the spec writes it
  const auto at = [&](WrapMode m) {
    return double(sampleTexture(tex, samplerWith(TextureFilter::Linear, TextureFilter::Linear, m), s, 0.5f, -1.0).r);
  };
  CHECK(std::abs(at(WrapMode::Repeat) - ((1 - a) * 30 + a * 0) / 255.0) < 1e-7);        // −1 → 3
  CHECK(std::abs(at(WrapMode::ClampToEdge) - 0.0) < 1e-7);                             // −1 → 0
  CHECK(std::abs(at(WrapMode::MirroredRepeat) - 0.0) < 1e-7);                          // −1 → 0
}

TEST_CASE("texture: the level of detail selects levels as §8.14.3 writes it", "[texture]") {
  Texture2D tex = textureOf(4, 4, [](int, int) { return 0; });
  tex.setLevel(1, constantLevel(2, 2, 100));
  tex.setLevel(2, constantLevel(1, 1, 200));
  const auto red = [&](TextureFilter min, double lambda) {
    return double(sampleTexture(tex, samplerWith(min, TextureFilter::Linear), 0.3f, 0.6f, lambda).r) * 255.0;
  };
  // Magnified for λ ≤ 0: level 0 whatever the minification filter.
  CHECK(red(TextureFilter::LinearMipmapLinear, -1.0) == Approx(0.0));
  CHECK(red(TextureFilter::LinearMipmapLinear, 0.0) == Approx(0.0));
  // Nearest level: d = 0 up to λ = ½, then ⌈λ + ½⌉ − 1, then q = 2.
  CHECK(red(TextureFilter::NearestMipmapNearest, 0.4) == Approx(0.0));
  CHECK(red(TextureFilter::NearestMipmapNearest, 0.5) == Approx(0.0));
  CHECK(red(TextureFilter::NearestMipmapNearest, 0.6) == Approx(100.0));
  CHECK(red(TextureFilter::NearestMipmapNearest, 1.5) == Approx(100.0));
  CHECK(red(TextureFilter::NearestMipmapNearest, 1.6) == Approx(200.0));
  CHECK(red(TextureFilter::LinearMipmapNearest, 9.0) == Approx(200.0));
  // Between levels: (1 − frac λ)·τ(⌊λ⌋) + frac λ·τ(⌊λ⌋ + 1), q from λ ≥ 2 on.
  CHECK(red(TextureFilter::LinearMipmapLinear, 0.25) == Approx(25.0));
  CHECK(red(TextureFilter::NearestMipmapLinear, 1.5) == Approx(150.0));
  CHECK(red(TextureFilter::LinearMipmapLinear, 2.5) == Approx(200.0));
  // The sampler's bias and clamp come first (§8.14.1).
  SamplerState sp = samplerWith(TextureFilter::LinearMipmapLinear, TextureFilter::Linear);
  sp.lodBias = 1.0f;
  CHECK(double(sampleTexture(tex, sp, 0.3f, 0.6f, 0.25).r) * 255.0 == Approx(125.0));
  sp.lodBias = 0.0f, sp.maxLod = 1.0f;
  CHECK(double(sampleTexture(tex, sp, 0.3f, 0.6f, 1.75).r) * 255.0 == Approx(100.0));
}

TEST_CASE("texture: an incomplete texture reads (0, 0, 0, 1)", "[texture]") {
  Texture2D tex = textureOf(4, 4, [](int, int) { return 200; });
  const SamplerState mipmapped;  // GL's default minification: NEAREST_MIPMAP_LINEAR
  CHECK(sampleTexture(tex, mipmapped, 0.5f, 0.5f, 1.0) == glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  tex.generateMipmaps();
  CHECK(tex.levels() == 3);
  CHECK(sampleTexture(tex, mipmapped, 0.5f, 0.5f, 1.0).r == float(200 / 255.0));
}

TEST_CASE("texture: the box filter rounds each mean to nearest, ties to even", "[texture]") {
  // An integer oracle: the mean of four bytes is S/4; round half to even on the quotient.
  const Texture2D tex = textureOf(8, 6, [](int i, int j) { return (i * 37 + j * 91 + i * j * 13) % 256; });
  const TextureLevel next = generateMipmapLevel(TextureFormat::Rgba8, tex.level(0));
  REQUIRE((next.width == 4 && next.height == 3));
  const TextureLevel& l0 = tex.level(0);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) {
      auto r = [&](int x, int y) { return int(l0.texels[(size_t(y) * 8 + size_t(x)) * 4]); };
      const int sum = r(2 * i, 2 * j) + r(2 * i + 1, 2 * j) + r(2 * i, 2 * j + 1) + r(2 * i + 1, 2 * j + 1);
      const int q = sum >> 2, rem = sum & 3;
      const int want = rem < 2 ? q : rem > 2 ? q + 1 : q + (q & 1);
      CHECK(int(next.texels[(size_t(j) * 4 + size_t(i)) * 4]) == want);
    }
  // Odd sizes: 5 × 1 → 2 × 1 reads texels 0–3; a one-texel-wide edge reads itself twice.
  const Texture2D odd = textureOf(5, 1, [](int i, int) { return 40 * i; });
  const TextureLevel half = generateMipmapLevel(TextureFormat::Rgba8, odd.level(0));
  REQUIRE((half.width == 2 && half.height == 1));
  CHECK(int(half.texels[0]) == 20);   // (0 + 40 + 0 + 40) / 4
  CHECK(int(half.texels[4]) == 100);  // (80 + 120 + 80 + 120) / 4
}

TEST_CASE("texture: sRGB texels decode by the spec's transfer function", "[texture]") {
  // IEC 61966-2-1's tabulated value: encoded 0.5 is linear 0.214041140…
  CHECK(srgbToLinear(0.5) == Approx(0.21404114).epsilon(1e-8));
  CHECK(srgbToLinear(0.04045) == Approx(0.04045 / 12.92));
  for (int k = 0; k < 256; ++k) REQUIRE(std::abs(linearToSrgb(srgbToLinear(k / 255.0)) - k / 255.0) < 1e-12);
  const Texture2D tex = textureOf(1, 1, [](int, int) { return 128; }, TextureFormat::Srgb8Alpha8);
  CHECK(tex.texel(0, 0, 0).r == srgbToLinear(128 / 255.0));
  CHECK(tex.texel(0, 0, 0).a == 1.0);  // alpha is never sRGB
}

TEST_CASE("texture: the level of detail of a quad's derivatives", "[texture]") {
  CHECK(lodFromDerivatives(1.0 / 256, 0, 0, 1.0 / 256, 256, 256) == Approx(0.0).margin(1e-12));  // a texel a pixel
  CHECK(lodFromDerivatives(2.0 / 256, 0, 0, 1.0 / 256, 256, 256) == Approx(1.0));  // the larger axis counts
  CHECK(lodFromDerivatives(0, 3.0 / 64, 0, 0, 64, 64) == Approx(std::log2(3.0)));
}

TEST_CASE("texture: bad sizes are refused with the numbers", "[texture]") {
  CHECK_THROWS_WITH(Texture2D(TextureFormat::Rgba8, 0, 4, {}), Catch::Contains("at least 1x1"));
  CHECK_THROWS_WITH(Texture2D(TextureFormat::Rgba8, 2, 2, std::vector<uint8_t>(15)), Catch::Contains("needs 16 bytes, got 15"));
  Texture2D tex = textureOf(4, 4, [](int, int) { return 0; });
  CHECK_THROWS_WITH(tex.setLevel(1, constantLevel(4, 4, 0)), Catch::Contains("must be 2x2"));
  CHECK_THROWS_WITH(tex.setLevel(2, constantLevel(1, 1, 0)), Catch::Contains("levels 1..1"));
  CHECK_THROWS_WITH(parseWrapMode("wrap"), Catch::Contains("unknown wrap mode 'wrap'"));
}

}  // namespace oitref::test
