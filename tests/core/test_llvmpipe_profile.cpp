// The llvmpipe profile's rules on hand-derived cases. The rules themselves were measured against
// Mesa 22.3's llvmpipe with `oitref glcheck blend` (CI runs it: tests/CMakeLists.txt, label
// glcheck); these cases pin the arithmetic so a change to the model shows here first.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "oitref/core/blend.h"
#include "oitref/core/format.h"
#include "oitref/core/profile.h"

using namespace oitref;

namespace {

struct Texel {
  uint8_t bytes[16] = {};
};

Texel blendOnce(const char* format, const BlendState& st, glm::vec4 dst, glm::vec4 src, const Profile& p) {
  const Format f = parseFormat(format);
  Texel t;
  encodeTexel(f, dst, p, t.bytes);
  blendIntoTexel(f, st, glm::vec4(0.0f), p, src, t.bytes);
  return t;
}

uint32_t word(const Texel& t) {
  uint32_t w;
  std::memcpy(&w, t.bytes, 4);
  return w;
}

}  // namespace

TEST_CASE("llvmpipe: a one-channel UNORM target blends complementary factors as a lerp", "[blend][llvmpipe]") {
  // s = 51, a = 128, d = 204. lerp: x = 128 + (128 >> 7) = 129; (129·(51 − 204) + 128) >> 8 = −77;
  // 204 − 77 = 127. The two-product form gives 26 + 102 = 128 (what rgba8 gets).
  const BlendState over = BlendState::same(BlendEquation::Add, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha);
  CHECK(blendOnce("r8", over, {0.8f, 0, 0, 0}, {0.2f, 0, 0, 0.5f}, llvmpipeProfile()).bytes[0] == 127);
  CHECK(blendOnce("rgba8", over, {0.8f, 0, 0, 0}, {0.2f, 0, 0, 0.5f}, llvmpipeProfile()).bytes[0] == 128);
}

TEST_CASE("llvmpipe: rgb10a2 goes through 16-bit integers, colour narrowed by truncation", "[blend][llvmpipe][unorm]") {
  // 0.23433097·65535 = 15357.3 → 15357; >> 6 = 239 (exact rounding of ·1023 gives 240).
  // Alpha 0.16666669·65535 = 10922.5 → 10922 (ties to even); ((10922 >> 2)·3 + 2^13) >> 14 = 0 (exact: 1).
  const BlendState replace = BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::Zero);
  const glm::vec4 v(0.23433096706867218f, 0, 0, 0x1.555558p-3f);
  CHECK(word(blendOnce("rgb10a2", replace, {0, 0, 0, 0}, v, llvmpipeProfile())) == 0x000000efu);
  CHECK(word(blendOnce("rgb10a2", replace, {0, 0, 0, 0}, v, exactProfile())) == 0x400000f0u);
}

TEST_CASE("llvmpipe: float targets fold constant factors, so signed zeros differ from GL's literal equation", "[blend][llvmpipe]") {
  // r32f has no alpha: ONE_MINUS_DST_ALPHA becomes ZERO and its term is never computed; the
  // source term is −1.5·min(As, 0) = −0, and −0 + (folded) stays −0. Literally: −0 + +0 = +0.
  const BlendState st = BlendState::same(BlendEquation::Add, BlendFactor::SrcAlphaSaturate, BlendFactor::OneMinusDstAlpha);
  CHECK(word(blendOnce("r32f", st, {2, 0, 0, 0}, {-1.5f, 0, 0, 0x1p25f}, llvmpipeProfile())) == 0x80000000u);
  CHECK(word(blendOnce("r32f", st, {2, 0, 0, 0}, {-1.5f, 0, 0, 0x1p25f}, exactProfile())) == 0x00000000u);
}

TEST_CASE("llvmpipe: one-channel float OVER is a fused lerp d + a·(s − d)", "[blend][llvmpipe]") {
  const float s = 0.1f, d = 0.7f, a = 0.3f;
  const float delta = s - d;  // one fp32 rounding, as the JIT code does
  // Oracle: the exact a·delta + d in long double (48-bit product, operands within 2^16 of each
  // other), rounded once to fp32.
  const float lerp = float((long double)a * (long double)delta + (long double)d);
  const float literal = s * a + d * (1.0f - a);
  const BlendState over = BlendState::same(BlendEquation::Add, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha);
  uint32_t want, lit;
  std::memcpy(&want, &lerp, 4);
  std::memcpy(&lit, &literal, 4);
  CHECK(word(blendOnce("r32f", over, {d, 0, 0, 0}, {s, 0, 0, a}, llvmpipeProfile())) == want);
  CHECK(word(blendOnce("r32f", over, {d, 0, 0, 0}, {s, 0, 0, a}, exactProfile())) == lit);
  CHECK(want == 0x3f051eb8u);  // what llvmpipe wrote (glcheck)
}

TEST_CASE("llvmpipe: denormals are flushed in float blending unless a small-float target is bound", "[blend][llvmpipe]") {
  const BlendState add = BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::One);
  // (s + d)·ONE with s = 2^-140: DAZ reads s as +0.
  CHECK(word(blendOnce("r32f", add, {0, 0, 0, 0}, {0x1p-140f, 0, 0, 0}, llvmpipeProfile())) == 0u);
  CHECK(word(blendOnce("r32f", add, {0, 0, 0, 0}, {0x1p-140f, 0, 0, 0}, exactProfile())) == 0x00000200u);
}
