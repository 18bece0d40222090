// Depth formats and compare functions, hand-derived.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "oitref/core/depth.h"
#include "oitref/core/pipeline_state.h"
#include "pipeline/depth_batch.h"
#include "support.h"

using namespace oitref;

TEST_CASE("depth: conversion to the buffer format rounds the exact product to nearest even", "[depth]") {
  CHECK(encodeDepth(0.5, DepthFormat::D16) == 32768);       // 32767.5 -> even
  CHECK(encodeDepth(0.5, DepthFormat::D24) == 8388608);     // 8388607.5 -> even
  CHECK(encodeDepth(1.0, DepthFormat::D16) == 65535);
  CHECK(encodeDepth(1.0 / 65535.0 * 2.5, DepthFormat::D16) == 2);  // 2.5 -> 2
  CHECK(encodeDepth(-0.25, DepthFormat::D24) == 0);          // clamped to the depth range
  CHECK(encodeDepth(1.5, DepthFormat::D24) == 0xffffff);
  CHECK(encodeDepth(std::nan(""), DepthFormat::D16) == 0);
  CHECK(encodeDepth(0.1, DepthFormat::D32F) == test::toBits(0.1f));
  CHECK(encodeDepth(-1.0, DepthFormat::D32F) == 0);
  CHECK(decodeDepth(32768, DepthFormat::D16) == 32768.0 / 65535.0);
}

TEST_CASE("depth: every compare function against its truth table", "[depth]") {
  // (fragment, stored): less, equal, greater.
  const uint32_t pairs[3][2] = {{1, 2}, {2, 2}, {3, 2}};
  const bool truth[8][3] = {
      {false, false, false},  // never
      {true, false, false},   // less
      {false, true, false},   // equal
      {true, true, false},    // lequal
      {false, false, true},   // greater
      {true, false, true},    // notequal
      {false, true, true},    // gequal
      {true, true, true},     // always
  };
  for (DepthFormat fmt : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F})
    for (int f = 0; f < 8; ++f)
      for (int p = 0; p < 3; ++p) {
        uint32_t a = pairs[p][0], b = pairs[p][1];
        if (fmt == DepthFormat::D32F) a = test::toBits(float(a) / 4), b = test::toBits(float(b) / 4);
        INFO(toString(fmt) << " " << toString(CompareFunc(f)) << " case " << p);
        CHECK(depthTestPasses(CompareFunc(f), a, b, fmt) == truth[f][p]);
      }
  for (int f = 0; f < 8; ++f) CHECK(parseCompareFunc(toString(CompareFunc(f))) == CompareFunc(f));
  CHECK_THROWS_WITH(parseCompareFunc("lesser"), Catch::Contains("lequal"));
}

TEST_CASE("depth: the compare sees converted values, so nearby depths collide in d16", "[depth]") {
  const double a = 0.5, b = 0.5 + 0.2 / 65535.0;  // both quantise to 32768
  const uint32_t qa = encodeDepth(a, DepthFormat::D16), qb = encodeDepth(b, DepthFormat::D16);
  CHECK(qa == qb);
  CHECK_FALSE(depthTestPasses(CompareFunc::Less, qb, qa, DepthFormat::D16));
  CHECK(depthTestPasses(CompareFunc::LEqual, qb, qa, DepthFormat::D16));
  // d24 and d32f keep them apart.
  CHECK(encodeDepth(a, DepthFormat::D24) != encodeDepth(b, DepthFormat::D24));
}

TEST_CASE("depth: buffers clear and store in their own width", "[depth]") {
  DepthBuffer d16(DepthFormat::D16, 4, 4);
  CHECK(d16.load(3, 3) == 65535);
  d16.clear(0.25);
  CHECK(d16.load(0, 0) == encodeDepth(0.25, DepthFormat::D16));
  CHECK(d16.sizeBytes() == 32);
  DepthBuffer d24(DepthFormat::D24, 4, 4);
  d24.store(1, 2, 123);
  CHECK(d24.load(1, 2) == 123);
  CHECK(d24.sizeBytes() == 64);
}

TEST_CASE("pipeline state: defaults are GL's initial state and print every field", "[depth]") {
  const PipelineState st;
  CHECK_FALSE(st.depth.testEnabled);             // glDisable(GL_DEPTH_TEST)
  CHECK(st.depth.func == CompareFunc::Less);     // GL_LESS
  CHECK(st.depth.writeMask);                     // glDepthMask(GL_TRUE)
  for (const BlendState& b : st.blend) {
    CHECK_FALSE(b.enabled);
    CHECK(b.equationRgb == BlendEquation::Add);  // GL_FUNC_ADD
    CHECK(b.srcRgb == BlendFactor::One);         // GL_ONE
    CHECK(b.dstRgb == BlendFactor::Zero);        // GL_ZERO
    CHECK(b.writeMask == 0xf);                   // glColorMask(TRUE, TRUE, TRUE, TRUE)
  }
  CHECK(st.blendConstant == glm::vec4(0.0f));    // glBlendColor(0, 0, 0, 0)
  CHECK(st.raster.frontFace == FrontFace::CounterClockwise);
  CHECK(st.profile == exactProfile());
  PipelineState other = st;
  other.blend[3].writeMask = 0x7;
  CHECK_FALSE(other == st);
  CHECK_THAT(other.describe(), Catch::Contains("blend[3]: blend off mask=rgb-") && Catch::Contains("depth: test=off func=less"));
}

// The span path's early test (pipeline/depth_batch.h) runs four lanes at a time with a scalar
// tail; its results and writes must be the per-fragment rules' (encodeDepth, depthTestPasses),
// and its encoding an independent closed form's: std::nearbyint of the exact double product
// (ties to even in the default rounding mode), fp32 rounding for d32f.
TEST_CASE("depth: the span kernels give the per-fragment test's results and writes", "[depth]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-0.25, 1.25);
  for (DepthFormat format : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F}) {
    const double maxCode = format == DepthFormat::D16 ? 65535.0 : 16777215.0;
    for (int f = 0; f < 8; ++f)
      for (bool write : {false, true}) {
        const CompareFunc func = CompareFunc(f);
        DepthBuffer buffer(format, 64, 2), oracle(format, 64, 2);
        for (int x = 0; x < 64; ++x) {
          const double stored = unit(rng);
          buffer.store(x, 1, encodeDepth(stored, format));
          oracle.store(x, 1, encodeDepth(stored, format));
        }
        for (int n : {64, 63, 7, 4, 3, 1}) {
          double z[64];
          for (int i = 0; i < n; ++i) {
            const int kind = int(rng() % 8);
            // Ties of the UNORM rounding, the range's ends, NaN, a stored value itself, or random.
            z[i] = kind == 0   ? (double(rng() % 1000) + 0.5) / maxCode
                   : kind == 1 ? (rng() % 2 ? 0.0 : 1.0)
                   : kind == 2 ? std::nan("")
                   : kind == 3 ? decodeDepth(oracle.load(i, 1), format)
                               : unit(rng);
            if (format != DepthFormat::D32F && kind < 2) {
              const double clamped = std::isnan(z[i]) ? 0.0 : std::clamp(z[i], 0.0, 1.0);
              REQUIRE(encodeDepth(z[i], format) == uint32_t(std::nearbyint(clamped * maxCode)));
            }
          }
          int passed[64];
          const int count = detail::depthBatchTest(format, func, write)(buffer, 0, 1, z, n, passed);
          std::vector<int> expected;
          for (int i = 0; i < n; ++i) {
            const uint32_t fragment = encodeDepth(z[i], format);
            if (!depthTestPasses(func, fragment, oracle.load(i, 1), format)) continue;
            expected.push_back(i);
            if (write) oracle.store(i, 1, fragment);
          }
          REQUIRE(std::vector<int>(passed, passed + count) == expected);
          for (int x = 0; x < 64; ++x) REQUIRE(buffer.load(x, 1) == oracle.load(x, 1));
        }
      }
  }
}

TEST_CASE("depth: the encoding over four lanes is the scalar encoding", "[depth]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-0.5, 1.5);
  for (int trial = 0; trial < 20000; ++trial) {
    lanes::d4 z;
    for (int l = 0; l < 4; ++l) z[l] = trial % 5 == 0 ? (double(rng() % 100000) + 0.5) / 16777215.0 : unit(rng);
    // The ends and what lies beyond them, and ½, which is a tie in both fixed-point formats
    // (32767.5, 8388607.5: even codes 32768, 8388608).
    if (trial < 3) z = trial == 0 ? lanes::d4{0.5, 0.0, 1.0, -0.0} : trial == 1 ? lanes::d4{NAN, INFINITY, -INFINITY, 0x1p-1074}
                                                                           : lanes::d4{0x1p-30, 1.0 - 0x1p-53, 1.0 + 0x1p-52, -0x1p-1074};
    const lanes::u4 d16 = encodeDepthAs<DepthFormat::D16>(z), d24 = encodeDepthAs<DepthFormat::D24>(z),
                    d32 = encodeDepthAs<DepthFormat::D32F>(z);
    for (int l = 0; l < 4; ++l) {
      REQUIRE(d16[l] == encodeDepth(z[l], DepthFormat::D16));
      REQUIRE(d24[l] == encodeDepth(z[l], DepthFormat::D24));
      REQUIRE(d32[l] == encodeDepth(z[l], DepthFormat::D32F));
      const double clamped = std::isnan(z[l]) ? 0.0 : std::clamp(z[l], 0.0, 1.0);
      REQUIRE(d24[l] == uint32_t(std::nearbyint(clamped * 16777215.0)));
    }
  }
}
