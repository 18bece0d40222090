// fp16 against Imath's software half (compiled in this file without F16C, see CMakeLists.txt):
// an independent implementation of round-to-nearest-even. Imath keeps NaN payloads without
// forcing the quiet bit, so NaN inputs are compared as "both NaN".
#include <catch2/catch.hpp>

#include <Imath/half.h>

#include "oitref/core/fp16.h"
#include "support.h"

using namespace oitref;

#if defined(__F16C__)
#error "this file must be compiled without F16C so Imath uses its software conversion"
#endif

TEST_CASE("fp16: portable converter matches Imath half on 4M random and boundary inputs", "[fp16][imath]") {
  oitref::test::BitStream bits(777);
  std::vector<float> inputs;
  for (int i = 0; i < 4'000'000; ++i) inputs.push_back(oitref::test::fromBits(bits.next()));
  for (float v : oitref::test::neighbourhood(65504.0f, 40)) inputs.push_back(v);
  for (float v : oitref::test::neighbourhood(65520.0f, 40)) inputs.push_back(v);
  for (float v : oitref::test::neighbourhood(std::ldexp(1.0f, -14), 40)) inputs.push_back(v);
  for (float v : oitref::test::neighbourhood(std::ldexp(1.0f, -25), 40)) inputs.push_back(v);
  for (float v : oitref::test::neighbourhood(std::ldexp(1.5f, -24), 40)) inputs.push_back(v);
  size_t compared = 0;
  for (float v : inputs) {
    if (std::isnan(v)) continue;
    const uint16_t ours = encodeHalfPortable(v, Rounding::NearestEven);
    const uint16_t imath = imath_float_to_half(v);
    if (ours != imath) FAIL("input " << v << ": ours " << std::hex << ours << ", Imath " << imath);
    ++compared;
  }
  CHECK(compared > 3'900'000);
  for (uint32_t h = 0; h < 65536; ++h) {
    const float a = decodeHalfPortable(uint16_t(h)), b = imath_half_to_float(uint16_t(h));
    if (std::isnan(a)) REQUIRE(std::isnan(b));
    else REQUIRE(oitref::test::toBits(a) == oitref::test::toBits(b));
  }
}
