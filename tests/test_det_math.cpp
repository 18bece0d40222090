// The deterministic exp/log used by the methods, against the C library over their ranges.
#include <catch2/catch.hpp>

#include "methods/det_math.h"
#include "support.h"

using namespace oitref;

TEST_CASE("det math: exp and log agree with libm to a few double ulps", "[detmath]") {
  test::BitStream rng(42);
  double worstExp = 0, worstLog = 0;
  for (int i = 0; i < 400000; ++i) {
    const double x = double(rng.uniform(-40.0f, 40.0f)) + double(rng.uniform(-1, 1)) * 1e-7;
    worstExp = std::max(worstExp, std::abs(methods::detExp(x) - std::exp(x)) / std::exp(x));
    const double y = std::ldexp(1.0 + double(rng.nextFloat01()), int(rng.next() % 120) - 60);
    worstLog = std::max(worstLog, std::abs(methods::detLog(y) - std::log(y)) / std::max(1e-300, std::abs(std::log(y))));
  }
  INFO("worst relative error: exp " << worstExp << ", log " << worstLog);
  CHECK(worstExp < 4e-16);
  CHECK(worstLog < 4e-16);
  CHECK(methods::detExp(0.0) == 1.0);
  CHECK(methods::detLog(1.0) == 0.0);
  CHECK(std::isinf(methods::detExp(1000.0)));
  CHECK(methods::detExp(-1000.0) == 0.0);
  CHECK(methods::detLog(0.0) == -INFINITY);
  CHECK(std::isnan(methods::detLog(-1.0)));
}

TEST_CASE("det math: sin and cos agree with libm to a few double ulps", "[detmath]") {
  test::BitStream rng(7);
  double worst = 0;
  for (int i = 0; i < 400000; ++i) {
    const double x = double(rng.uniform(-8.0f, 8.0f)) + double(rng.uniform(-1, 1)) * 1e-7;
    const methods::SinCos sc = methods::detSinCos(x);
    worst = std::max({worst, std::abs(sc.sin - std::sin(x)), std::abs(sc.cos - std::cos(x))});
  }
  INFO("worst absolute error " << worst);
  CHECK(worst < 4e-16);
  CHECK(methods::detSinCos(0.0).sin == 0.0);
  CHECK(methods::detSinCos(0.0).cos == 1.0);
  CHECK(std::isnan(methods::detSinCos(INFINITY).sin));
}
