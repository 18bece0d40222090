// llvmpipe's log and exp (oitref/core/shader_builtins.h). The scalar functions are checked
// against the driver itself by glcheck scene (MBOIT's b0 and weights, bit for bit); here the
// batch forms, whose vector lanes must give the scalar functions' bits, and the polynomials'
// accuracy against the exact values, which bounds how far a transcription slip could hide.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "oitref/core/shader_builtins.h"
#include "util/seeded_random.h"

using namespace oitref;

namespace {

std::vector<float> arguments(double lo, double hi, uint64_t seed) {
  util::SeededRandom rng(seed);
  std::vector<float> x;
  for (int i = 0; i < 100000; ++i) x.push_back(float(rng.uniform(lo, hi)));
  for (int i = 0; i < 200; ++i) x.push_back(x[size_t(i)]);  // runs of one value (the batch's shortcut)
  for (float v : {0.0f, -0.0f, 1.0f, 0.5f, 2.0f, -126.99999f, 88.0f, -88.0f, 1e-30f, 3.0e38f}) x.push_back(v);
  return x;
}

}  // namespace

TEST_CASE("llvmpipe exp and log batches give the scalar functions' bits", "[shader_builtins]") {
  for (bool fused : {true, false}) {
    for (auto [lo, hi] : {std::pair{-100.0, 100.0}, std::pair{-1.0, 1.0}}) {
      const std::vector<float> x = arguments(lo, hi, 7);
      std::vector<float> out(x.size());
      llvmpipe::expBatch(x.data(), out.data(), int(x.size()), fused);
      for (size_t i = 0; i < x.size(); ++i) {
        INFO("exp(" << x[i] << ") fused " << fused);
        REQUIRE(std::bit_cast<uint32_t>(out[i]) == std::bit_cast<uint32_t>(llvmpipe::exp(x[i], fused)));
      }
    }
    const std::vector<float> x = arguments(1e-6, 10.0, 11);
    std::vector<float> out(x.size());
    llvmpipe::logBatch(x.data(), out.data(), int(x.size()), fused);
    for (size_t i = 0; i < x.size(); ++i) {
      INFO("log(" << x[i] << ") fused " << fused);
      REQUIRE(std::bit_cast<uint32_t>(out[i]) == std::bit_cast<uint32_t>(llvmpipe::log(x[i], fused)));
    }
  }
}

TEST_CASE("llvmpipe exp2 and log2 are close to the exact values, exact where Mesa makes them so", "[shader_builtins]") {
  // Relative error of the degree-5 exp2 and degree-4 log2 minimax fits in fp32: a few 1e-7.
  util::SeededRandom rng(3);
  double worstExp = 0.0, worstLog = 0.0;
  for (int i = 0; i < 100000; ++i) {
    const float x = float(rng.uniform(-20.0, 20.0));
    worstExp = std::max(worstExp, std::fabs(double(llvmpipe::exp2(x, true)) / std::exp2(double(x)) - 1.0));
    const float y = float(rng.uniform(1e-3, 1e3));
    worstLog = std::max(worstLog, std::fabs(double(llvmpipe::log2(y, true)) - std::log2(double(y))));
  }
  CHECK(worstExp < 2e-6);
  CHECK(worstLog < 2e-6);
  // Whole powers of two: the polynomial's constant term is 1, the mantissa of 2^k is 1.
  for (int k = -20; k <= 20; ++k) {
    CHECK(llvmpipe::exp2(float(k), true) == std::ldexp(1.0f, k));
    CHECK(llvmpipe::log2(std::ldexp(1.0f, k), true) == float(k));
  }
  CHECK(llvmpipe::log2(0.0f, true) == -INFINITY);
  CHECK(std::isnan(llvmpipe::log2(-1.0f, true)));
  CHECK(llvmpipe::log2(INFINITY, true) == INFINITY);
  CHECK(llvmpipe::exp2(200.0f, true) == INFINITY);  // clamped to 128: 2^128 overflows
}
