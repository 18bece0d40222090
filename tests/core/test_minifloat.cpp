// Minifloats against MinifloatOracle (oracles.h), which shares no code with the converter.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>

#include "oitref/core/minifloat.h"
#include "oracles.h"
#include "support.h"

using namespace oitref;
using oitref::test::MinifloatOracle;

namespace {

std::vector<MinifloatSpec> specsUnderTest() {
  return {kHalfSpec,     kFloat11Spec, kFloat10Spec, kBfloat16Spec, kFp8E5M2Spec, kFp8E4M3Spec,
          parseMinifloatSpec("e3m2"), parseMinifloatSpec("e4m3nonan"), parseMinifloatSpec("e5m10_ftz"),
          parseMinifloatSpec("e2m1"), parseMinifloatSpec("e5m6u_sat"), parseMinifloatSpec("e6m9")};
}

}  // namespace

TEST_CASE("minifloat: every spec matches the enumerating oracle at midpoints and random inputs", "[minifloat]") {
  for (const MinifloatSpec& spec : specsUnderTest()) {
    INFO("spec " << spec.name());
    const MinifloatOracle oracle(spec);
    std::vector<float> inputs;
    // Every representable value, the midpoints between neighbours, and fp32 neighbours of both.
    for (size_t i = 0; i < oracle.positive.size(); ++i) {
      inputs.push_back(float(oracle.positive[i].first));
      if (i + 1 < oracle.positive.size()) {
        const double mid = 0.5 * (oracle.positive[i].first + oracle.positive[i + 1].first);
        for (float v : oitref::test::neighbourhood(float(mid), 2)) inputs.push_back(v);
      }
    }
    for (float v : oitref::test::neighbourhood(float(oracle.maxFinite * 1.0625), 2)) inputs.push_back(v);
    for (float v : oitref::test::neighbourhood(float(oracle.maxFinite * 2.5), 1)) inputs.push_back(v);
    oitref::test::BitStream rng(5);
    for (int i = 0; i < 200'000; ++i) {
      const float v = oitref::test::fromBits(rng.next());
      if (std::isfinite(v)) inputs.push_back(v);
    }
    inputs.erase(std::remove_if(inputs.begin(), inputs.end(), [](float v) { return !std::isfinite(v); }), inputs.end());
    const size_t n = inputs.size();
    for (size_t i = 0; i < n; ++i) inputs.push_back(-inputs[i]);
    for (float v : inputs)
      for (Rounding r : {Rounding::NearestEven, Rounding::TowardZero}) {
        const uint32_t got = encodeMinifloat(v, spec, r), want = oracle.encode(v, r);
        if (got != want)
          FAIL("input " << v << " (" << std::hex << oitref::test::toBits(v) << ") rounding "
                        << (r == Rounding::NearestEven ? "rne" : "rtz") << ": got " << got << ", oracle " << want);
      }
  }
}

TEST_CASE("minifloat: decode is exact and every finite code round-trips", "[minifloat]") {
  for (const MinifloatSpec& spec : specsUnderTest()) {
    INFO("spec " << spec.name());
    const MinifloatOracle oracle(spec);
    for (const auto& [value, code] : oracle.positive) {
      if (!spec.denormals && oracle.isDenormalCode(code)) {
        REQUIRE(decodeMinifloat(code, spec) == 0.0f);
        continue;
      }
      REQUIRE(double(decodeMinifloat(code, spec)) == value);
      REQUIRE(encodeMinifloat(float(value), spec, Rounding::NearestEven) == code);
      REQUIRE(encodeMinifloat(float(value), spec, Rounding::TowardZero) == code);
    }
    CHECK(double(largestFiniteMinifloat(spec)) == oracle.maxFinite);
  }
}

TEST_CASE("minifloat: fp32 as e8m23 is the identity", "[minifloat]") {
  const MinifloatSpec fp32{8, 23, true, FloatSpecials::Ieee, true, false};
  oitref::test::BitStream rng(11);
  for (int i = 0; i < 1'000'000; ++i) {
    const uint32_t u = rng.next();
    const float v = oitref::test::fromBits(u);
    if (std::isnan(v)) continue;
    REQUIRE(encodeMinifloat(v, fp32, Rounding::NearestEven) == u);
    REQUIRE(oitref::test::toBits(decodeMinifloat(u, fp32)) == u);
  }
}

TEST_CASE("minifloat: bfloat16 matches the bit-trick oracle", "[minifloat]") {
  oitref::test::BitStream rng(3);
  for (int i = 0; i < 2'000'000; ++i) {
    const uint32_t u = rng.next();
    if (std::isnan(oitref::test::fromBits(u))) continue;
    // Round to nearest even on the top 16 bits of the pattern (overflow carries into inf).
    const uint32_t rne = (u + 0x7fffu + ((u >> 16) & 1u)) >> 16;
    REQUIRE(encodeMinifloat(oitref::test::fromBits(u), kBfloat16Spec, Rounding::NearestEven) == rne);
    // Toward zero is truncation of the pattern (even above the largest finite value).
    REQUIRE(encodeMinifloat(oitref::test::fromBits(u), kBfloat16Spec, Rounding::TowardZero) == u >> 16);
  }
}

TEST_CASE("minifloat: F11/F10 and fp8 hand-derived special cases (GL 4.6 §2.3.4.3–4, OCP fp8)", "[minifloat]") {
  for (Rounding r : {Rounding::NearestEven, Rounding::TowardZero}) {
    CHECK(encodeMinifloat(1.0f, kFloat11Spec, r) == 0x3c0);
    CHECK(encodeMinifloat(65024.0f, kFloat11Spec, r) == 0x7bf);    // largest finite F11
    CHECK(encodeMinifloat(65500.0f, kFloat11Spec, r) == 0x7bf);    // past it: saturates (GL)
    CHECK(encodeMinifloat(1e30f, kFloat11Spec, r) == 0x7bf);
    CHECK(encodeMinifloat(INFINITY, kFloat11Spec, r) == 0x7c0);    // +inf stays inf
    CHECK(encodeMinifloat(-INFINITY, kFloat11Spec, r) == 0);       // -inf -> 0
    CHECK(encodeMinifloat(-1.0f, kFloat11Spec, r) == 0);           // negatives -> 0
    CHECK(encodeMinifloat(-0.0f, kFloat11Spec, r) == 0);
    CHECK((encodeMinifloat(-NAN, kFloat11Spec, r) & 0x7c0) == 0x7c0);  // ±NaN -> +NaN
    CHECK((encodeMinifloat(-NAN, kFloat11Spec, r) & 0x3f) != 0);
    CHECK(encodeMinifloat(64512.0f, kFloat10Spec, r) == 0x3df);    // largest finite F10
    CHECK(encodeMinifloat(65000.0f, kFloat10Spec, r) == 0x3df);
    CHECK(encodeMinifloat(448.0f, kFp8E4M3Spec, r) == 0x7e);       // E4M3 max
    CHECK(encodeMinifloat(1000.0f, kFp8E4M3Spec, r) == 0x7e);      // saturates: no inf
    CHECK(encodeMinifloat(INFINITY, kFp8E4M3Spec, r) == 0x7e);
    CHECK(encodeMinifloat(NAN, kFp8E4M3Spec, r) == 0x7f);
    CHECK(encodeMinifloat(-NAN, kFp8E4M3Spec, r) == 0xff);
  }
  CHECK(encodeMinifloat(464.0f, kFp8E4M3Spec, Rounding::NearestEven) == 0x7e);  // tie 448|480: even
  CHECK(encodeMinifloat(57344.0f, kFp8E5M2Spec, Rounding::NearestEven) == 0x7b);  // E5M2 max
  CHECK(encodeMinifloat(61440.0f, kFp8E5M2Spec, Rounding::NearestEven) == 0x7c);  // midpoint -> inf
  CHECK(std::isnan(decodeMinifloat(0x7f, kFp8E4M3Spec)));
  CHECK(decodeMinifloat(0x7e, kFp8E4M3Spec) == 448.0f);
  CHECK(decodeMinifloat(0x3c0, kFloat11Spec) == 1.0f);
  CHECK(std::isinf(decodeMinifloat(0x7c0, kFloat11Spec)));
  // Flush to zero: the smallest fp16 denormal is 0 with _ftz; the smallest normal survives.
  const MinifloatSpec ftz = parseMinifloatSpec("e5m10_ftz");
  CHECK(encodeMinifloat(std::ldexp(1.0f, -24), ftz, Rounding::NearestEven) == 0);
  CHECK(encodeMinifloat(std::ldexp(1.0f, -14), ftz, Rounding::NearestEven) == 0x400);
  CHECK(decodeMinifloat(0x0001, ftz) == 0.0f);
}

TEST_CASE("minifloat: spec strings parse, print and reject nonsense", "[minifloat]") {
  CHECK(parseMinifloatSpec("e8m7") == kBfloat16Spec);
  CHECK(parseMinifloatSpec("e4m3fn") == kFp8E4M3Spec);
  CHECK(parseMinifloatSpec("e5m6u_sat") == kFloat11Spec);
  CHECK(kFp8E4M3Spec.name() == "e4m3fn");
  // Counts past int's range (std::stoi threw std::out_of_range there: found by fuzz_blend_csv).
  for (const char* bad : {"", "m3", "e9m3", "e4m0", "e4m24", "e4m3x", "e4m3ufn", "e1m3", "e33333333333333333333m3",
                          "e4m99999999999", "e1000m3"})
    CHECK_THROWS_AS(parseMinifloatSpec(bad), std::invalid_argument);
  CHECK_THROWS_WITH(parseMinifloatSpec("e33333333333333333333m3"), Catch::Contains("too large"));
}
