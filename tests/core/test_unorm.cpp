// UNORM conversion against an integer-arithmetic oracle: the exact value f·(2^b−1) compared with
// half-integers using 128-bit integers, no floating point involved.
#include <catch2/catch.hpp>

#include <atomic>

#include <tbb/parallel_for.h>

#include "blend/blend_math.h"
#include "oitref/core/unorm.h"
#include "oracles.h"
#include "support.h"

using namespace oitref;
using oitref::test::fromBits;
using oitref::test::oracleUnorm;

namespace {

uint32_t fp32ProductRounding(float f, int b) {
  const float p = f * float((1u << b) - 1);
  return uint32_t(std::nearbyint(p));
}

// The floats in [0,1] where rounding the fp32 product first gives another code than the exact
// rule: they sit within a few ulps of (k + ½)/255.
std::vector<float> disputedUnorm8Inputs() {
  std::vector<float> out;
  for (int k = 0; k < 255; ++k)
    for (float v : oitref::test::neighbourhood(float((k + 0.5) / 255.0), 8))
      if (oracleUnorm(v, 8) != fp32ProductRounding(v, 8)) out.push_back(v);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

TEST_CASE("unorm8: exact rule matches the integer oracle on the disputed inputs and 1M random", "[unorm]") {
  const std::vector<float> disputed = disputedUnorm8Inputs();
  // The count, and dEQP's: 128 floats in [0,1] where lrintf(f*255.0f) is wrong.
  REQUIRE(disputed.size() == 128);
  CHECK(oitref::test::toBits(disputed.front()) == 0x3b008081u);  // 0.00196081... ≈ 0.5/255
  for (float v : disputed) {
    INFO("input bits " << std::hex << oitref::test::toBits(v));
    CHECK(encodeUnorm(v, 8, UnormRounding::ExactNearestEven) == oracleUnorm(v, 8));
    CHECK(encodeUnorm(v, 8, UnormRounding::Fp32Product) == fp32ProductRounding(v, 8));
    CHECK(encodeUnorm(v, 8, UnormRounding::Fp32Product) != oracleUnorm(v, 8));
  }
  oitref::test::BitStream rng(99);
  for (int i = 0; i < 1'000'000; ++i) {
    const float v = rng.nextFloat01() * 1.0000001f;
    for (int b : {2, 8, 10, 16, 24}) REQUIRE(encodeUnorm(v, b) == oracleUnorm(v, b));
  }
}

TEST_CASE("unorm: clamping, NaN and exact decode round trip", "[unorm]") {
  for (int b : {2, 8, 10, 16}) {
    const uint32_t max = (1u << b) - 1;
    CHECK(encodeUnorm(NAN, b) == 0);
    CHECK(encodeUnorm(-NAN, b) == 0);
    CHECK(encodeUnorm(-1.0f, b) == 0);
    CHECK(encodeUnorm(-0.0f, b) == 0);
    CHECK(encodeUnorm(-INFINITY, b) == 0);
    CHECK(encodeUnorm(2.0f, b) == max);
    CHECK(encodeUnorm(INFINITY, b) == max);
    for (uint32_t k = 0; k <= max; ++k) {
      const float v = decodeUnorm(k, b);
      REQUIRE(v == float(double(k) / double(max)));  // correctly rounded k/(2^b − 1)
      REQUIRE(encodeUnorm(v, b) == k);
      REQUIRE(encodeUnorm(v, b, UnormRounding::Fp32Product) == k);
      // Every rule encodes a decoded code back to it: MAX on UNORM8 targets blends in the codes
      // because of it (target_blender.cpp, maxInCodes).
      if (b <= 12) REQUIRE(encodeUnorm(v, b, UnormRounding::NvidiaFixed) == k);
    }
  }
  // Hand-derived: 0.5·255 = 127.5 -> 128 (even); 0.5·1023 = 511.5 -> 512; 0.5·3 = 1.5 -> 2.
  CHECK(encodeUnorm(0.5f, 8) == 128);
  CHECK(encodeUnorm(0.5f, 10) == 512);
  CHECK(encodeUnorm(0.5f, 2) == 2);
  CHECK(encodeUnorm(1.5f / 255.0f, 8) == 2);  // fp32(1.5/255)·255 is just above 1.5
}

TEST_CASE("unorm8: exact rule matches the oracle on every float in [0,1]", "[.][exhaustive][unorm]") {
  std::atomic<uint64_t> mismatches{0}, disputed{0};
  tbb::parallel_for(uint32_t(0), uint32_t(0x3f800000 / 65536 + 1), [&](uint32_t hi) {
    uint64_t bad = 0, diff = 0;
    for (uint32_t lo = 0; lo < 65536; ++lo) {
      const uint32_t u = (hi << 16) | lo;
      if (u > 0x3f800000u) break;
      const float v = fromBits(u);
      const uint32_t exact = oracleUnorm(v, 8);
      bad += encodeUnorm(v, 8) != exact;
      diff += fp32ProductRounding(v, 8) != exact;
    }
    mismatches += bad;
    disputed += diff;
  });
  CHECK(mismatches == 0);
  CHECK(disputed == 128);
}

TEST_CASE("unorm: the four-wide encoder gives encodeUnorm's bits", "[unorm]") {
  std::vector<float> inputs = disputedUnorm8Inputs();
  oitref::test::BitStream rng(123);
  for (int i = 0; i < 200000; ++i) inputs.push_back(rng.uniform(-0.5f, 1.5f));
  for (float v : {NAN, -NAN, INFINITY, -INFINITY, 0.0f, -0.0f, 1.0f, 0.5f}) inputs.push_back(v);
  for (size_t i = 0; i + 4 <= inputs.size(); ++i)
    for (int b : {8, 10, 2})
      for (UnormRounding r : {UnormRounding::ExactNearestEven, UnormRounding::Fp32Product}) {
        const detail::v4f v{inputs[i], inputs[i + 1], inputs[i + 2], inputs[i + 3]};
        const detail::v4i got = detail::encodeUnorm4(v, b, r);
        for (int k = 0; k < 4; ++k) REQUIRE(uint32_t(got[k]) == encodeUnorm(v[k], b, r));
      }
}
