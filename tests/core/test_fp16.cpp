// fp16: our portable converter against the F16C instruction (an independent implementation in
// silicon), plus hand-derived boundary cases. The Imath oracle is in test_fp16_imath.cpp.
#include <catch2/catch.hpp>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <atomic>

#include <tbb/parallel_for.h>

#include "oitref/core/fp16.h"
#include "support.h"

using namespace oitref;
using oitref::test::fromBits;

namespace {

#if defined(__x86_64__)

__attribute__((target("f16c"))) uint16_t f16cEncode(float f, Rounding r) {
  return r == Rounding::TowardZero ? _cvtss_sh(f, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)
                                   : _cvtss_sh(f, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
}
__attribute__((target("f16c"))) float f16cDecode(uint16_t h) { return _cvtsh_ss(h); }
#else
uint16_t f16cEncode(float, Rounding) { return 0; }
float f16cDecode(uint16_t) { return 0; }
#endif

}  // namespace

TEST_CASE("fp16: every one of the 65536 halves decodes and re-encodes to itself", "[fp16]") {
  for (uint32_t h = 0; h < 65536; ++h) {
    for (Rounding r : {Rounding::NearestEven, Rounding::TowardZero}) {
      const float v = decodeHalfPortable(uint16_t(h));
      const uint16_t back = encodeHalfPortable(v, r);
      const bool isNan = (h & 0x7c00) == 0x7c00 && (h & 0x3ff);
      if (isNan) {
        // NaN stays NaN, sign and payload kept, quiet bit set.
        REQUIRE(back == uint16_t(h | 0x200));
      } else {
        REQUIRE(back == h);
      }
      REQUIRE(encodeHalf(decodeHalf(uint16_t(h)), r) == back);
    }
  }
}

TEST_CASE("fp16: hand-derived boundary cases", "[fp16]") {
  struct Case { float in; uint16_t rne, rtz; };
  const Case cases[] = {
      {0.0f, 0x0000, 0x0000},
      {-0.0f, 0x8000, 0x8000},
      {1.0f, 0x3c00, 0x3c00},
      {65504.0f, 0x7bff, 0x7bff},                    // largest finite
      {fromBits(0x477fefff), 0x7bff, 0x7bff},        // 65519.998: below the midpoint to 65536
      {65520.0f, 0x7c00, 0x7bff},                    // the midpoint: ties to even = inf; RTZ: max finite
      {1e6f, 0x7c00, 0x7bff},
      {-1e6f, 0xfc00, 0xfbff},
      {INFINITY, 0x7c00, 0x7c00},
      {-INFINITY, 0xfc00, 0xfc00},
      {std::ldexp(1.0f, -14), 0x0400, 0x0400},       // smallest normal
      {std::ldexp(1023.0f, -24), 0x03ff, 0x03ff},    // largest denormal
      {std::ldexp(1023.5f, -24), 0x0400, 0x03ff},    // tie between them: even (0x400)
      {std::ldexp(1.0f, -24), 0x0001, 0x0001},       // smallest denormal
      {std::ldexp(1.0f, -25), 0x0000, 0x0000},       // half of it: tie to even 0
      {std::ldexp(1.0f, -25) * 1.0000001f, 0x0001, 0x0000},
      {std::ldexp(1.5f, -24), 0x0002, 0x0001},       // tie between 1 and 2: even
      {std::ldexp(2.5f, -24), 0x0002, 0x0002},       // tie between 2 and 3: even
      {1.0f + std::ldexp(1.0f, -11), 0x3c00, 0x3c00},        // tie: even (1.0)
      {1.0f + 3 * std::ldexp(1.0f, -11), 0x3c02, 0x3c01},    // tie: even (1 + 2^-9)
      {-(1.0f + 3 * std::ldexp(1.0f, -11)), 0xbc02, 0xbc01},
      {0.1f, 0x2e66, 0x2e66},
      {1e-8f, 0x0000, 0x0000},
  };
  for (const Case& c : cases) {
    INFO("input " << c.in);
    CHECK(encodeHalfPortable(c.in, Rounding::NearestEven) == c.rne);
    CHECK(encodeHalfPortable(c.in, Rounding::TowardZero) == c.rtz);
    CHECK(encodeHalf(c.in, Rounding::NearestEven) == c.rne);
    CHECK(encodeHalf(c.in, Rounding::TowardZero) == c.rtz);
  }
  CHECK(encodeHalfPortable(NAN, Rounding::NearestEven) == 0x7e00);
  CHECK(encodeHalfPortable(-NAN, Rounding::NearestEven) == 0xfe00);
  CHECK(encodeHalfPortable(fromBits(0x7f800001), Rounding::NearestEven) == 0x7e00);  // sNaN -> quiet
}

TEST_CASE("fp16: F16C and the portable converter agree on 4M random and boundary inputs", "[fp16]") {
  if (!cpuHasF16C()) {
    WARN("CPU without F16C: comparison skipped");
    return;
  }
  oitref::test::BitStream bits(12345);
  std::vector<float> inputs;
  for (int i = 0; i < 4'000'000; ++i) inputs.push_back(fromBits(bits.next()));
  // Around every binade boundary and midpoint of the half range, both signs.
  for (int e = -26; e <= 16; ++e)
    for (float m : {1.0f, 1.5f, 1.0009765625f, 1.00048828125f, 1.99951171875f})
      for (float v : oitref::test::neighbourhood(std::ldexp(m, e), 3)) {
        inputs.push_back(v);
        inputs.push_back(-v);
      }
  for (float v : inputs)
    for (Rounding r : {Rounding::NearestEven, Rounding::TowardZero}) {
      const uint16_t ours = encodeHalfPortable(v, r), hw = f16cEncode(v, r);
      if (ours != hw) FAIL("input bits " << std::hex << oitref::test::toBits(v) << ": ours " << ours << ", F16C " << hw);
    }
  for (uint32_t h = 0; h < 65536; ++h) {
    const float a = decodeHalfPortable(uint16_t(h)), b = f16cDecode(uint16_t(h));
    REQUIRE(oitref::test::toBits(a) == oitref::test::toBits(b));
  }
}

TEST_CASE("fp16: F16C and the portable converter agree on all 2^32 inputs", "[.][exhaustive][fp16]") {
  if (!cpuHasF16C()) return;
  std::atomic<uint64_t> mismatches{0};
  tbb::parallel_for(uint32_t(0), uint32_t(1u << 16), [&](uint32_t hi) {
    uint64_t bad = 0;
    for (uint32_t lo = 0; lo < 65536; ++lo) {
      const float v = fromBits((hi << 16) | lo);
      bad += encodeHalfPortable(v, Rounding::NearestEven) != f16cEncode(v, Rounding::NearestEven);
      bad += encodeHalfPortable(v, Rounding::TowardZero) != f16cEncode(v, Rounding::TowardZero);
    }
    mismatches += bad;
  });
  REQUIRE(mismatches == 0);
}
