// exp and log in plain double arithmetic (+, −, ×, ÷ only), so a method's shader math gives the
// same bits on every machine: C libraries choose among exp/log implementations by CPU (e.g.
// glibc's FMA variants), and GPUs use their own approximations anyway. Accurate to a few double
// ulps (the test checks 4e-16 relative against libm), then rounded once to fp32 by the caller.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "oitref/core/lanes.h"

namespace oitref::methods {

// ln 2 in two parts (the high one with trailing zero bits, so k·kLn2Hi is exact for the k of
// detExp's range) and log2(e): the reductions of detExp, its batch and detLog.
constexpr double kLn2Hi = 0.693147180369123816490, kLn2Lo = 1.90821492927058770002e-10;
constexpr double kLog2E = 1.44269504088896338700;
// r = x − k·ln2, in detExp's order of operations, on one value or on lanes.
template <typename D>
inline D detExpRemainder(D x, D k) {
  return (x - k * kLn2Hi) - k * kLn2Lo;
}

// e^x for n ≤ 16 arguments: x = k·ln2 + r with |r| ≤ ln2/2, then a Taylor polynomial of r to
// degree 16 in Horner form (NaN stays NaN, above 709 infinity, below −745 zero). Each argument
// takes its own operations, so the bits do not depend on n; the arguments' chains of sixteen
// dependent divisions run side by side, so that they overlap (the DFAOIT training's sigmoids).
inline void detExpMany(const double* x, double* out, int n) {
  double k[16], r[16], p[16];
  for (int i = 0; i < n; ++i) {
    const bool regular = !(std::isnan(x[i]) || x[i] > 709.0 || x[i] < -745.0);
    k[i] = regular ? std::nearbyint(x[i] * kLog2E) : 0.0;
    r[i] = regular ? detExpRemainder(x[i], k[i]) : 0.0;
    p[i] = 1.0;
  }
  for (int m = 16; m >= 1; --m)
    for (int i = 0; i < n; ++i) p[i] = 1.0 + p[i] * r[i] / m;  // Horner form of Σ r^m / m!
  for (int i = 0; i < n; ++i)
    out[i] = std::isnan(x[i]) ? x[i]
             : x[i] > 709.0   ? std::numeric_limits<double>::infinity()
             : x[i] < -745.0  ? 0.0
                              : std::ldexp(p[i], int(k[i]));
}
inline double detExp(double x) {
  double e;
  detExpMany(&x, &e, 1);
  return e;
}

// Four lanes of doubles, and of their integer bits.
typedef double v4d __attribute__((vector_size(32)));
typedef int64_t v4l __attribute__((vector_size(32)));

// Four groups of four lanes from x[0…lanes), lanes ≤ 16, the rest `fill`. The callers fill x a
// double at a time just before, so each lane is loaded on its own (lanes::loadEachLane).
template <typename V>
inline void loadLanes(const double* x, int lanes, double fill, V (&v)[4]) {
  double padded[16];
  if (lanes < 16) {
    for (int i = 0; i < 16; ++i) padded[i] = i < lanes ? x[i] : fill;
    x = padded;
  }
  for (int g = 0; g < 4; ++g) v[g] = lanes::loadEachLane<V>(x + 4 * g);
}

// A float from a double approximation y of a value v known to satisfy |v − y| ≤ 2^−43·|y|: where
// the interval y·(1 ± 2^−40) rounds to one float, that float is float(v) (rounding is monotone,
// and the interval holds v with a margin of 8). Lanes where it does not (v within 2^−40 of a
// float's rounding boundary: about one in 10^4) and lanes not `regular` get `decided` 0. The
// callers' v and y each lie within 2^−44 of the true value: detExp within 200 double ulps of e^x
// (Horner's rounding bound for its three roundings a step, γ_48·e^(2|r|), |r| ≤ ln2/2 + 2^−40;
// its tail below 2^−56), detLog within a few ulps (its series' terms shrink by s² ≤ 0.03; the
// tests measure 4e−16 against libm), and the fast approximations as their comments say.
constexpr double kUndecidedBelow = 1.0 - 0x1p-40, kUndecidedAbove = 1.0 + 0x1p-40;
inline void floatIfDecided(v4d y, v4l regular, float* out, int32_t* decided) {
  typedef float v4f __attribute__((vector_size(16)));
  typedef int32_t v4i __attribute__((vector_size(16)));
  const v4f lo = __builtin_convertvector(y * kUndecidedBelow, v4f);
  const v4f hi = __builtin_convertvector(y * kUndecidedAbove, v4f);
  const v4i same = ((v4i)lo == (v4i)hi) & __builtin_convertvector(regular, v4i);
  std::memcpy(out, &lo, sizeof lo);
  std::memcpy(decided, &same, sizeof same);
}

// Lanes of a vector of doubles, or a scalar double (then K, the matching integer lanes, is int64_t).
template <typename D>
inline constexpr int kLanesOf = int(sizeof(D) / sizeof(double));
// nearbyint(v) for |v| < 2^51, round half to even: (v + 1.5·2^52) − 1.5·2^52 in the default
// rounding mode; the integer itself is in the low bits of the sum (`bits`).
template <typename D, typename K>
inline D nearbyintLanes(D v, K& bits) {
  constexpr double kRound = 6755399441055744.0;  // 1.5·2^52
  const D shifted = v + kRound;
  if constexpr (kLanesOf<D> == 1) bits = std::bit_cast<int64_t>(shifted) - std::bit_cast<int64_t>(kRound);
  else bits = (K)shifted - (K)(D{} + kRound);
  return shifted - kRound;
}
template <typename D, typename K>
inline D laneLookup(const double* table, K index) {
  if constexpr (kLanesOf<D> == 1) {
    return table[index];
  } else {
    D v;
    for (int l = 0; l < kLanesOf<D>; ++l) v[l] = table[index[l]];
    return v;
  }
}
// 2^e for −1022 ≤ e ≤ 1023, built in the exponent bits.
template <typename D, typename K>
inline D twoTo(K e) {
  if constexpr (kLanesOf<D> == 1) return std::bit_cast<double>(uint64_t(e + 1023) << 52);
  else return (D)((e + 1023) << 52);
}

// The `lanes` results of a batch's 16 lanes: result[i] where decided[i], else exact(i). One
// store when all sixteen are decided (nearly always).
template <typename Exact>
inline void storeDecided(const float* result, const int32_t* decided, int lanes, float* out, Exact exact) {
  typedef int32_t v4i __attribute__((vector_size(16)));
  v4i all;
  std::memcpy(&all, decided, sizeof all);
  for (int g = 1; g < 4; ++g) {
    v4i d;
    std::memcpy(&d, decided + 4 * g, sizeof d);
    all &= d;
  }
  if (lanes == 16 && (all[0] & all[1] & all[2] & all[3])) {
    std::memcpy(out, result, 16 * sizeof(float));
    return;
  }
  for (int i = 0; i < lanes; ++i) out[i] = decided[i] ? result[i] : exact(i);
}

// float(f(x)) for n arguments, sixteen lanes at a time in four groups of four (the lanes past n
// hold `fill`): reduce(v, regular) gives a group's reduced lanes and marks those it can take,
// finish(reduced) the approximation floatIfDecided decides, exact(x) float(f(x)) itself for the
// lanes left undecided. All groups are reduced before any is finished, so that their chains
// overlap.
template <typename Reduce, typename Finish, typename Exact>
inline void decidedFloatBatch(const double* x, float* out, int n, double fill, Reduce reduce, Finish finish, Exact exact) {
  constexpr int kGroups = 4;
  for (int start = 0; start < n; start += 4 * kGroups) {
    const int lanes = n - start < 4 * kGroups ? n - start : 4 * kGroups;
    v4d v[kGroups];
    loadLanes(x + start, lanes, fill, v);
    v4l regular[kGroups];
    decltype(reduce(v[0], regular[0])) reduced[kGroups];
    for (int g = 0; g < kGroups; ++g) reduced[g] = reduce(v[g], regular[g]);
    float result[4 * kGroups];
    int32_t decided[4 * kGroups];
    for (int g = 0; g < kGroups; ++g) floatIfDecided(finish(reduced[g]), regular[g], result + 4 * g, decided + 4 * g);
    storeDecided(result, decided, lanes, out + start, [&](int i) { return exact(x[start + i]); });
  }
}

// 2^(j/128) for j < 128: e^(j·ln2/128) by its Taylor series in double, summed at compile time
// (within 2^−50 relative; the tests check it against exp2l).
inline constexpr std::array<double, 128> kExp2Table = [] {
  std::array<double, 128> t{};
  for (int j = 0; j < 128; ++j) {
    const double a = j * (kLn2Hi + kLn2Lo) / 128.0;
    double term = 1.0, sum = 1.0;
    for (int m = 1; m <= 30; ++m) term = term * a / m, sum += term;
    t[size_t(j)] = sum;
  }
  return t;
}();
// detExpFloatBatch's approximation of e^x for |x| ≤ 700: x = (128·K + j)·ln2/128 + r with
// |r| ≤ ln2/256 (a little more where the product x·128/ln2 rounded: the bound allows 0.0028), then
// 2^K·2^(j/128)·(1 + r + r²/2 + r³/6 + r⁴/24). Its error: the polynomial's tail below 2^−49
// relative, the table's 2^−50, r's rounding (ln2/128 in two parts; the high part's 32 bits times
// k, below 2^17, are exact) and the roundings of Horner's steps and the products below 2^−50
// together: within 2^−47 of e^x (floatIfDecided's premise).
// The result is normal for |x| ≤ 700, so 2^K is exact.
// In two steps, so that a batch's groups of lanes can run each step side by side: the reduction
// (r, the table's 2^(j/128) and 2^K) and the polynomial.
template <typename D>
struct ExpReduced {
  D r, scale;
};
template <typename D, typename K>
inline ExpReduced<D> detExpReduce(D x) {
  K k;
  const D kd = nearbyintLanes(x * (kLog2E * 128.0), k);
  return {(x - kd * (kLn2Hi / 128.0)) - kd * (kLn2Lo / 128.0), laneLookup<D>(kExp2Table.data(), k & 127) * twoTo<D>(k >> 7)};
}
template <typename D>
inline D detExpFinish(const ExpReduced<D>& t) {
  const D r = t.r;
  return (1.0 + r * (1.0 + r * (0.5 + r * (1.0 / 6.0 + r * (1.0 / 24.0))))) * t.scale;
}
template <typename D, typename K>
inline D detExpFastLanes(D x) {
  return detExpFinish(detExpReduce<D, K>(x));
}
inline double detExpFast(double x) { return detExpFastLanes<double, int64_t>(x); }

// float(detExp(x)) for n arguments, what MBOIT's and MT's weights take, without detExp's 16
// divisions where they cannot change the float: detExpFastLanes in lanes, then floatIfDecided;
// detExp itself for the undecided lanes and for x outside [−700, 700] or NaN. Four groups of four
// lanes side by side, so that their chains of multiply-adds overlap.
inline void detExpFloatBatch(const double* x, float* out, int n) {
  decidedFloatBatch(
      x, out, n, 0.0,
      [](v4d v, v4l& regular) {
        regular = (v == v) & (v <= 700.0) & (v >= -700.0);
        return detExpReduce<v4d, v4l>(regular ? v : v4d{});
      },
      [](const ExpReduced<v4d>& t) { return detExpFinish(t); }, [](double a) { return float(detExp(a)); });
}

// ln x: x = m·2^e with m in [√½, √2), ln m = 2·atanh(s), s = (m − 1)/(m + 1), |s| ≤ 0.172,
// series to s^33. detLogReduce splits x (false for the special inputs, whose result it gives);
// detLogSeries finishes on one value (D = double) or four lanes (D = v4d, detLogBatch).
inline bool detLogReduce(double x, double& s, double& e, double& special) {
  if (std::isnan(x) || x < 0.0) return special = std::numeric_limits<double>::quiet_NaN(), false;
  if (x == 0.0) return special = -std::numeric_limits<double>::infinity(), false;
  if (std::isinf(x)) return special = x, false;
  int exponent = 0;
  double m = std::frexp(x, &exponent);  // m in [0.5, 1)
  if (m < 0.70710678118654752440) m *= 2.0, --exponent;
  s = (m - 1.0) / (m + 1.0);
  e = double(exponent);
  return true;
}
template <typename D>
inline D detLogSeries(D s, D e) {
  const D s2 = s * s;
  D series{};
  for (int n = 33; n >= 1; n -= 2) series = 1.0 / n + s2 * series;
  return (2.0 * s * series + e * kLn2Lo) + e * kLn2Hi;
}
inline double detLog(double x) {
  double s = 0.0, e = 0.0, special = 0.0;
  return detLogReduce(x, s, e, special) ? detLogSeries(s, e) : special;
}

// Whether x[0…n) are one bit pattern. Out of line: inlined into shaders whose arrays are filled
// for a count GCC cannot bound, it warned that x[0] may be unset.
[[gnu::noinline]] inline bool allSameBits(const double* x, int n) {
  uint64_t first;
  std::memcpy(&first, x, sizeof first);
  for (int i = 1; i < n; ++i) {
    uint64_t bits;
    std::memcpy(&bits, x + i, sizeof bits);
    if (bits != first) return false;
  }
  return true;
}

// Where x[0…n), n > 1, are one bit pattern: out[i] = f(x[0]) for each (f a pure function of the
// bits, so the same as each alone), and true.
template <typename T, typename F>
inline bool fillIfOneValue(const double* x, int n, T* out, F f) {
  if (n <= 1 || !allSameBits(x, n)) return false;
  const T r = f(x[0]);
  for (int i = 0; i < n; ++i) out[i] = r;
  return true;
}

// detLog's reduction on four lanes: x = m·2^e with m in [√½, √2), frexp built from the bits
// (x = f·2^(E − 1023) with f in [1, 2) gives frexp's m = f/2 in [0.5, 1), the mantissa under the
// biased exponent 1022, and exponent E − 1022, exact; the exponent as a double by the 2^52 trick,
// exact below 2^52). True in the lanes of normal positive arguments; the others reduce 1.
template <typename V, typename L = int64_t __attribute__((vector_size(32)))>
inline L logReduceLanes(V x, V& m, V& e) {
  constexpr double kMinNormal = 2.2250738585072014e-308, kTwo52 = 4503599627370496.0;
  const L regular = (x >= kMinNormal) & (x <= 1.7976931348623157e308);  // false for NaN
  const L bits = (L)(regular ? x : V{} + 1.0);
  m = (V)((bits & 0x000fffffffffffffLL) | (int64_t(1022) << 52));
  e = (V)(((bits >> 52) & 0x7ff) | (L)(V{} + kTwo52)) - kTwo52 - 1022.0;
  const L low = m < 0.70710678118654752440;
  m = low ? m * 2.0 : m;
  e = low ? e - 1.0 : e;
  return regular;
}

// detLog of n arguments in vector lanes, each lane taking detLog's operations in its order (so
// the same bits). Four groups of four lanes at a time, so that their chains of 17 dependent
// multiply-adds overlap (one group's chain alone left the core waiting). Normal positive
// arguments are reduced in the lanes (logReduceLanes); zero, subnormal, negative, infinite and NaN
// arguments take detLogReduce one at a time.
//
// A batch whose arguments are all one value (one bit pattern: a material's constant alpha, say)
// takes detLog once; a pure function of the bits, so the same bits as each alone.
inline void detLogBatch(const double* x, double* out, int n) {
  if (fillIfOneValue(x, n, out, detLog)) return;
  constexpr int kGroups = 4;
  for (int start = 0; start < n; start += 4 * kGroups) {
    const int lanes = n - start < 4 * kGroups ? n - start : 4 * kGroups;
    v4d v[kGroups], s[kGroups], e[kGroups], r[kGroups];
    v4l regular[kGroups];
    loadLanes(x + start, lanes, 1.0, v);  // lanes past n: any regular value
    for (int g = 0; g < kGroups; ++g) {
      v4d m;
      regular[g] = logReduceLanes(v[g], m, e[g]);
      s[g] = (m - 1.0) / (m + 1.0);
    }
    for (int g = 0; g < kGroups; ++g) r[g] = detLogSeries(s[g], e[g]);  // inlined: the groups' chains interleave
    for (int i = 0; i < lanes; ++i) {
      const int g = i / 4, l = i % 4;
      if (regular[g][l]) {
        out[start + i] = r[g][l];
      } else {
        double si = 0.0, ei = 0.0, special = 0.0;
        out[start + i] = detLogReduce(x[start + i], si, ei, special) ? detLogSeries(si, ei) : special;
      }
    }
  }
}

// ln c and 1/c for c = j/128, j from 90 to 182 (the rest unused): ln c = 2·atanh((c − 1)/(c + 1))
// by its series in double at compile time (within 2^−50 of |ln c|; the tests check both against
// long double).
struct LogTables {
  std::array<double, 183> lnC{}, inverseC{};
};
inline constexpr LogTables kLogTables = [] {
  LogTables t;
  for (size_t j = 90; j <= 182; ++j) {
    const double c = double(j) / 128.0, s = (c - 1.0) / (c + 1.0), s2 = s * s;
    double series = 0.0;
    for (int k = 41; k >= 1; k -= 2) series = 1.0 / k + s2 * series;
    t.lnC[j] = 2.0 * s * series;
    t.inverseC[j] = 1.0 / c;
  }
  return t;
}();
// detLogFloatBatch's approximation of ln(m·2^e) for m in [√½, √2) (logReduceLanes): c =
// nearbyint(128·m)/128, so m − c is exact (Sterbenz) with |m − c| ≤ 2^−8; r = (m − c)·(1/c),
// |r| < 0.0056, and ln m = ln c + ln(1 + r), ln(1 + r) to r⁶/6. The tail is below 2^−47 of |ln m|
// (|ln m| ≥ 2^−8.1 where c ≠ 1; where c = 1 it is r⁶/7 relative). ln c and ln(1 + r) cancel by at
// most a factor 3.5, e·ln2 and ln m not at all (|ln m| ≤ ln2/2): with the table's error and the
// roundings, within 2^−46 of ln x (floatIfDecided's premise).
// In two steps, as detExpReduce/detExpFinish: r, ln c and e, then the polynomial and the sum.
template <typename D>
struct LogReduced {
  D r, lnC, e;
};
template <typename D, typename K>
inline LogReduced<D> detLogTableReduce(D m, D e) {
  K j;
  const D c = nearbyintLanes(m * 128.0, j) * (1.0 / 128.0);
  return {(m - c) * laneLookup<D>(kLogTables.inverseC.data(), j), laneLookup<D>(kLogTables.lnC.data(), j), e};
}
template <typename D>
inline D detLogTableFinish(const LogReduced<D>& t) {
  const D r = t.r;
  const D p = r * (1.0 + r * (-0.5 + r * (1.0 / 3.0 + r * (-0.25 + r * (0.2 + r * (-1.0 / 6.0))))));
  return t.e * kLn2Hi + (t.lnC + (p + t.e * kLn2Lo));
}
template <typename D, typename K>
inline D detLogFastLanes(D m, D e) {
  return detLogTableFinish(detLogTableReduce<D, K>(m, e));
}
// For one normal positive x (detLogFloat, the tests).
inline double detLogFast(double x) {
  const uint64_t bits = std::bit_cast<uint64_t>(x);  // as logReduceLanes: frexp from the bits
  double m = std::bit_cast<double>((bits & 0x000fffffffffffffull) | uint64_t(1022) << 52);
  double e = double(int((bits >> 52) & 0x7ff) - 1022);
  if (m < 0.70710678118654752440) m *= 2.0, e -= 1.0;
  return detLogFastLanes<double, int64_t>(m, e);
}

// float(detLog(x)) for one x, as a lane of detLogFloatBatch computes it (a batch of one value).
inline float detLogFloat(double x) {
  if (!(x >= 2.2250738585072014e-308 && x <= 1.7976931348623157e308)) return float(detLog(x));
  const double y = detLogFast(x);
  const float lo = float(y * kUndecidedBelow), hi = float(y * kUndecidedAbove);
  return std::bit_cast<uint32_t>(lo) == std::bit_cast<uint32_t>(hi) ? lo : float(detLog(x));
}

// float(detLog(x)) for n arguments (MBOIT's and MT's optical depths), without detLog's series of
// 17 steps where it cannot change the float: detLogFastLanes, then floatIfDecided; detLog itself
// for the undecided lanes and the arguments that are not normal positive numbers. A batch of
// one bit pattern (a material's constant alpha: most of them) takes detLogFloat once.
inline void detLogFloatBatch(const double* x, float* out, int n) {
  if (fillIfOneValue(x, n, out, detLogFloat)) return;
  decidedFloatBatch(
      x, out, n, 1.0,
      [](v4d v, v4l& regular) {
        v4d m, e;
        regular = logReduceLanes(v, m, e);
        return detLogTableReduce<v4d, v4l>(m, e);
      },
      [](const LogReduced<v4d>& t) { return detLogTableFinish(t); }, [](double a) { return float(detLog(a)); });
}

// cos x and sin x for |x| ≤ 2^20: x = k·π/2 + r with |r| ≤ π/4 (π/2 in two parts, so r is
// accurate to a few ulps for the phases MBOIT uses, |x| ≤ 2π), Taylor polynomials of r to
// degree 22 / 21, then the quadrant k mod 4 picks and signs them.
struct SinCos {
  double sin, cos;
};
inline SinCos detSinCos(double x) {
  if (!std::isfinite(x) || std::fabs(x) > 0x1p20) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  constexpr double kPiOver2Hi = 1.57079632673412561417, kPiOver2Lo = 6.07710050650619224932e-11;
  const double k = std::nearbyint(x * 0.63661977236758134308);
  const double r = (x - k * kPiOver2Hi) - k * kPiOver2Lo, r2 = r * r;
  double s = 0.0, c = 0.0;
  for (int n = 21; n >= 3; n -= 2) s = (1.0 - s) * r2 / (double(n) * (n - 1));  // r − r³/3! + …
  s = r * (1.0 - s);
  for (int n = 22; n >= 2; n -= 2) c = (1.0 - c) * r2 / (double(n) * (n - 1));
  c = 1.0 - c;
  switch ((int64_t(k) % 4 + 4) % 4) {
    case 0: return {s, c};
    case 1: return {c, -s};
    case 2: return {-s, -c};
    default: return {-c, s};
  }
}

}  // namespace oitref::methods
