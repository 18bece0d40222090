// The deterministic exp/log used by the methods, against the C library over their ranges.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cfloat>
#include <limits>
#include <cmath>
#include <cstring>
#include <vector>

#include "methods/det_math.h"
#include "methods/power.h"
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

// powInt<N> (the WBOIT weights' unrolled form) against the loop it restates, bit for bit: every
// exponent the weights use and a few more, over random bit patterns (NaN, infinities, subnormals
// and zeros included) and over [0, 2], where the weights' depths lie.
template <unsigned N>
static void checkPowIntUnrolled(test::BitStream& rng) {
  for (int i = 0; i < 20000; ++i) {
    uint32_t bits = rng.next();
    float x;
    std::memcpy(&x, &bits, 4);
    if (i % 2) x = rng.uniform(0.0f, 2.0f);
    const float loop = methods::powInt(x, N), unrolled = methods::powInt<N>(x);
    uint32_t a, b;
    std::memcpy(&a, &loop, 4);
    std::memcpy(&b, &unrolled, 4);
    INFO("x = " << x << ", n = " << N);
    REQUIRE(a == b);
  }
}
TEST_CASE("powInt: the compile-time exponent multiplies as the loop does", "[detmath]") {
  test::BitStream rng(7);
  checkPowIntUnrolled<0>(rng), checkPowIntUnrolled<1>(rng), checkPowIntUnrolled<2>(rng);
  checkPowIntUnrolled<3>(rng), checkPowIntUnrolled<4>(rng), checkPowIntUnrolled<5>(rng);
  checkPowIntUnrolled<6>(rng), checkPowIntUnrolled<7>(rng), checkPowIntUnrolled<9>(rng);
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

TEST_CASE("det math: the batched float exp gives float(detExp) in every lane", "[detmath]") {
  // detExpFloatBatch decides most lanes from a polynomial without divisions and an error bound,
  // the rest through detExp: every lane must equal float(detExp(x)), bit for bit. Besides random
  // arguments, the special ones, the ends of the fast range, nearbyint's ties, and arguments whose
  // e^x lies within a few double ulps of a float's rounding boundary (half-way between two
  // floats, and the float boundary at the subnormals and at FLT_MAX): there the bound cannot
  // decide, and a lane that guessed would be wrong about half the time.
  test::BitStream rng(99);
  std::vector<double> x;
  for (const double special : {0.0, -0.0, 700.0, -700.0, 700.0000001, -700.0000001, 709.0, 709.5, -745.0, -745.5, 1e-300,
                               -1e-310, 0.3465735902799726, double(NAN), double(INFINITY), -double(INFINITY)})
    x.push_back(special);
  for (int i = 0; i < 200001; ++i)
    x.push_back(double(rng.uniform(-60.0f, 60.0f)) * (i % 7 == 0 ? 12.0 : 1.0) + double(rng.uniform(-1, 1)) * 1e-9);
  for (int k = -1075; k <= 1023; ++k) x.push_back((k + 0.5) / 1.44269504088896338700);
  int boundaries = 0;
  for (int i = 0; i < 20000; ++i) {
    // A random float f (normal, subnormal or near the top), the midpoint to its successor, and
    // arguments around log(midpoint).
    const int e = int(rng.next() % 276) - 150;
    const float f = std::ldexp(rng.uniform(1.0f, 2.0f), e);
    const double mid = (double(f) + double(std::nextafter(f, INFINITY))) / 2.0;
    if (!std::isfinite(mid) || mid <= 0.0) continue;
    double a = std::log(mid);
    for (int step = 0; step < 3; ++step, a = std::nextafter(a, INFINITY)) x.push_back(a);
    ++boundaries;
  }
  std::vector<float> batched(x.size());
  methods::detExpFloatBatch(x.data(), batched.data(), int(x.size()));
  size_t different = 0, ambiguous = 0;
  double worst = 0;  // |detExpFast − detExp| / detExp: the bound assumes at most 2^-40
  for (size_t i = 0; i < x.size(); ++i) {
    const double e = methods::detExp(x[i]);
    const float want = float(e);
    different += std::memcmp(&want, &batched[i], sizeof(float)) != 0;
    if (std::fabs(x[i]) <= 700.0) worst = std::max(worst, std::fabs(methods::detExpFast(x[i]) - e) / e);
    // How many arguments an error of 2^-40 could move across a boundary: the fallback's share.
    ambiguous += std::isfinite(e) && float(e * (1 - 0x1p-40)) != float(e * (1 + 0x1p-40));
  }
  INFO(ambiguous << " arguments need detExp itself; worst relative difference " << worst);
  CHECK(different == 0);
  CHECK(worst <= 0x1p-49);  // far inside the bound's 2^-40 (the analysis gives at most ~2^-45)
  CHECK(boundaries > 19000);
  CHECK(ambiguous > 10000);  // the boundary arguments reach the fallback
}

TEST_CASE("det math: the batched log gives detLog's bits in every lane", "[detmath]") {
  // detLogBatch runs four lanes' series together; each lane must equal detLog bit for bit (whose
  // accuracy against libm the first test checks), the special arguments and a count that is not
  // a multiple of four included.
  test::BitStream rng(98);
  std::vector<double> x;
  for (const double special : {0.0, -0.0, 1.0, 0.70710678118654752440, 0.7071067811865475, 2.0, 1e-310, -1.0,
                               double(NAN), double(INFINITY), -double(INFINITY), 1.0 - 0x1p-20})
    x.push_back(special);
  for (int i = 0; i < 100001; ++i)
    x.push_back(i % 3 == 0 ? double(rng.uniform(0.0f, 1.0f)) : std::ldexp(double(rng.uniform(0.5f, 1.0f)), int(rng.next() % 200) - 100));
  // Every mantissa bit, every exponent (the lanes build frexp from the bits), and the normal range's
  // ends and the subnormals beside them.
  for (const double end : {DBL_MAX, DBL_MIN, std::nextafter(DBL_MIN, 0.0), std::nextafter(DBL_MIN, 1.0), DBL_TRUE_MIN,
                           std::nextafter(0.70710678118654752440, 0.0), std::nextafter(0.70710678118654752440, 1.0)})
    x.push_back(end);
  for (int k = -1074; k <= 1023; ++k) {
    const uint64_t mantissa = (uint64_t(rng.next()) << 32 | rng.next()) & 0x000fffffffffffffull;
    double unit;  // in [1, 2) with the random mantissa
    const uint64_t bits = mantissa | uint64_t(1023) << 52;
    std::memcpy(&unit, &bits, sizeof unit);
    x.push_back(std::ldexp(unit, k));
  }
  std::vector<double> batched(x.size());
  methods::detLogBatch(x.data(), batched.data(), int(x.size()));
  size_t different = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double want = methods::detLog(x[i]);
    different += std::memcmp(&want, &batched[i], sizeof(double)) != 0;
  }
  CHECK(different == 0);
}

TEST_CASE("det math: the batched float log gives float(detLog) in every lane", "[detmath]") {
  // detLogFloatBatch decides most lanes from a table and a short series and an error bound, the
  // rest through detLog: every lane must equal float(detLog(x)), bit for bit, in batches of any
  // length and for detLogFloat (one argument). Besides random arguments, the special ones, the
  // reduction's edges (√½, the table's rounding ties m = (j + ½)/128), and arguments whose
  // logarithm lies within a few double ulps of a float's rounding boundary: there the bound cannot
  // decide, and a lane that guessed would be wrong about half the time.
  test::BitStream rng(97);
  std::vector<double> x;
  for (const double special : {0.0, -0.0, 1.0, 2.0, 0.5, 0.70710678118654752440, std::nextafter(0.70710678118654752440, 0.0),
                               std::nextafter(0.70710678118654752440, 1.0), 1.0 - 0x1p-20, 1.0 - 0x1p-53, 1.0 + 0x1p-52,
                               DBL_MIN, std::nextafter(DBL_MIN, 0.0), DBL_TRUE_MIN, DBL_MAX, -1.0, double(NAN),
                               double(INFINITY), -double(INFINITY)})
    x.push_back(special);
  for (int j = 90; j <= 182; ++j)
    for (const int e : {-3, 0, 5})
      for (const double m : {(j + 0.5) / 128.0, std::nextafter((j + 0.5) / 128.0, 0.0), std::nextafter((j + 0.5) / 128.0, 2.0)})
        x.push_back(std::ldexp(m, e));
  for (int i = 0; i < 200000; ++i)
    x.push_back(i % 2 ? double(rng.uniform(0.0f, 1.0f)) : std::ldexp(double(rng.uniform(0.5f, 1.0f)), int(rng.next() % 400) - 200));
  int boundaries = 0;
  for (int i = 0; i < 20000; ++i) {
    // A random float f among the logarithms of normal doubles, the midpoint to its successor,
    // and arguments around exp(midpoint).
    const float f = rng.uniform(-700.0f, 700.0f) * (i % 3 == 0 ? 1e-4f : 1.0f);
    const double mid = (double(f) + double(std::nextafter(f, INFINITY))) / 2.0;
    double a = std::exp(mid);
    if (!(a > DBL_MIN && a < DBL_MAX)) continue;
    a = std::nextafter(a, 0.0);
    for (int step = 0; step < 3; ++step, a = std::nextafter(a, INFINITY)) x.push_back(a);
    ++boundaries;
  }
  std::vector<float> batched(x.size()), chunked(x.size());
  methods::detLogFloatBatch(x.data(), batched.data(), int(x.size()));
  for (size_t start = 0; start < x.size(); start += 13)  // batches of 13: partial groups of lanes
    methods::detLogFloatBatch(x.data() + start, chunked.data() + start, int(std::min<size_t>(13, x.size() - start)));
  size_t different = 0, ambiguous = 0;
  double worst = 0;  // |detLogFast − detLog| / |detLog|: the bound assumes at most 2^-44
  for (size_t i = 0; i < x.size(); ++i) {
    const double l = methods::detLog(x[i]);
    const float want = float(l), one = methods::detLogFloat(x[i]);
    different += std::memcmp(&want, &batched[i], sizeof(float)) != 0;
    different += std::memcmp(&want, &chunked[i], sizeof(float)) != 0;
    different += std::memcmp(&want, &one, sizeof(float)) != 0;
    if (x[i] >= DBL_MIN && x[i] <= DBL_MAX && l != 0.0)
      worst = std::max(worst, std::fabs(methods::detLogFast(x[i]) - l) / std::fabs(l));
    ambiguous += std::isfinite(l) && float(l * (1 - 0x1p-40)) != float(l * (1 + 0x1p-40));
  }
  INFO(ambiguous << " arguments need detLog itself; worst relative difference " << worst);
  CHECK(different == 0);
  CHECK(worst <= 0x1p-46);  // the analysis's bound (det_math.h, detLogFastLanes)
  CHECK(boundaries > 19000);
  CHECK(ambiguous > 10000);  // the boundary arguments reach the fallback
}

TEST_CASE("det math: the fast exp's and log's tables against long double", "[detmath]") {
  // detExpFastLanes's 2^(j/128) and detLogFastLanes's ln(j/128) and 1/c, summed from series at
  // compile time: their error bounds (2^-50) enter the batches' analyses.
  double worstExp = 0, worstLn = 0;
  for (size_t j = 0; j < methods::kExp2Table.size(); ++j) {
    const long double want = std::exp2((long double)j / 128.0L);
    worstExp = std::max(worstExp, double(std::fabs((long double)methods::kExp2Table[j] - want) / want));
  }
  for (size_t j = 90; j <= 182; ++j) {
    const long double c = (long double)j / 128.0L, want = std::log(c);
    if (j == 128) CHECK(methods::kLogTables.lnC[j] == 0.0);
    else worstLn = std::max(worstLn, double(std::fabs((long double)methods::kLogTables.lnC[j] - want) / std::fabs(want)));
    CHECK(methods::kLogTables.inverseC[j] == 1.0 / (double(j) / 128.0));
  }
  INFO("worst relative error: 2^(j/128) " << worstExp << ", ln c " << worstLn);
  CHECK(worstExp <= 0x1p-50);
  CHECK(worstLn <= 0x1p-50);
}

TEST_CASE("det math: a batch of one repeated argument gives detLog's bits in every lane", "[detmath]") {
  // detLogBatch (detLogFloatBatch) takes detLog (detLogFloat) once for a batch whose arguments are
  // one bit pattern (a material's constant alpha); batches that differ in one place only,
  // anywhere, must not take that path.
  size_t different = 0, cases = 0;
  for (const double value : {0.25, 0.886, 1.0 - 0x1p-20, 0.0, -0.0, 1e-310, -1.0, double(NAN), double(INFINITY)})
    for (int n : {2, 3, 4, 15, 16, 17, 63, 64})
      for (int odd = -1; odd < n; ++odd) {  // −1: every argument the same
        std::vector<double> x(static_cast<size_t>(n), value), out(static_cast<size_t>(n));
        if (odd >= 0) x[size_t(odd)] = value == 0.25 ? 0.5 : 0.25;
        std::vector<float> outFloat(static_cast<size_t>(n));
        methods::detLogBatch(x.data(), out.data(), n);
        methods::detLogFloatBatch(x.data(), outFloat.data(), n);
        for (int i = 0; i < n; ++i) {
          const double want = methods::detLog(x[size_t(i)]);
          const float wantFloat = float(want);
          different += std::memcmp(&want, &out[size_t(i)], sizeof(double)) != 0;
          different += std::memcmp(&wantFloat, &outFloat[size_t(i)], sizeof(float)) != 0;
        }
        ++cases;
      }
  CHECK(cases == 9 * (3 + 4 + 5 + 16 + 17 + 18 + 64 + 65));
  CHECK(different == 0);
}

TEST_CASE("det math: detExpMany gives detExp's bits for every argument, special ones included", "[detmath]") {
  test::BitStream rng(7);
  std::vector<double> x;
  for (int i = 0; i < 20000; ++i) x.push_back(double(rng.uniform(-60.0f, 60.0f)) + double(rng.uniform(-1, 1)) * 1e-9);
  for (double v : {0.0, -0.0, 709.0, 709.5, -745.0, -745.5, -740.0, -708.5, 1e300, -1e300, std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN(), 1e-310})
    x.push_back(v);
  int compared = 0;
  for (size_t start = 0; start < x.size(); start += 13) {  // groups of 13 and a shorter last one
    const int n = int(std::min<size_t>(13, x.size() - start));
    double many[16];
    methods::detExpMany(x.data() + start, many, n);
    for (int i = 0; i < n; ++i, ++compared) {
      const double one = methods::detExp(x[start + size_t(i)]);
      INFO("x = " << x[start + size_t(i)]);
      CHECK(std::memcmp(&one, &many[i], sizeof one) == 0);
    }
  }
  CHECK(compared == int(x.size()));
}
