// exp and log in plain double arithmetic (+, −, ×, ÷ only), so a method's shader math gives the
// same bits on every machine: C libraries choose among exp/log implementations by CPU (e.g.
// glibc's FMA variants), and GPUs use their own approximations anyway. Accurate to a few double
// ulps (the test checks 4e-16 relative against libm), then rounded once to fp32 by the caller.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

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

// Four groups of four lanes from x[0…lanes), lanes ≤ 16, the rest `fill`: whole vectors where
// the groups are full (built lane by lane in memory, each vector load waited on the narrower
// stores before it: no store forwarding).
template <typename V>
inline void loadLanes(const double* x, int lanes, double fill, V (&v)[4]) {
  if (lanes == 16) {
    std::memcpy(v, x, sizeof v);
    return;
  }
  double padded[16];
  for (int i = 0; i < 16; ++i) padded[i] = i < lanes ? x[i] : fill;
  std::memcpy(v, padded, sizeof v);
}

// The polynomial of detExpFloatBatch: Σ r^m / m! for m ≤ 13 in Horner form, with coefficients
// 1/m! computed as 1/(m−1)! / m (within 13 ulps), on one value or on lanes.
template <typename D>
inline D detExpTaylor13(D r) {
  constexpr int kDegree = 13;
  constexpr auto kCoefficients = [] {
    std::array<double, kDegree + 1> c{};
    c[0] = 1.0;
    for (int m = 1; m <= kDegree; ++m) c[size_t(m)] = c[size_t(m - 1)] / m;
    return c;
  }();
  D q = D{} + kCoefficients[kDegree];
  for (int m = kDegree - 1; m >= 0; --m) q = q * r + kCoefficients[size_t(m)];
  return q;
}
// detExp's reduction and the polynomial, for |x| ≤ 700: what each lane of detExpFloatBatch
// computes before its rounding test (the tests check it against detExp).
inline double detExpFast(double x) {
  const double k = std::nearbyint(x * kLog2E);
  return std::ldexp(detExpTaylor13(detExpRemainder(x, k)), int(k));
}

// float(detExp(x)) for n arguments, what MBOIT's and MT's weights take, without detExp's 16
// divisions where they cannot change the float. Each lane computes detExpFast(x): detExp's k and r
// (nearbyint(v) for |v| < 2^51 as (v + 1.5·2^52) − 1.5·2^52 in the default rounding mode, round
// half to even), detExpTaylor13(r), scaled by 2^k (exact: the result is normal for |x| ≤ 700).
// That value and detExp's are both within 200 double ulps of 2^k·e^r for the shared r (Horner's
// rounding bound: γ_48·e^(2|r|) for detExp's three roundings a step, γ_27·e^(2|r|) plus the
// coefficients' 13 ulps here, |r| ≤ ln2/2 + 2^−40; the truncated tails are below 2^−56). So where
// the interval of ±2^−40 relative around the fast value rounds to one float, that float is
// float(detExp(x)) (rounding is monotone). Elsewhere — a value within 2^−40 of a float's rounding
// boundary, about one in 30,000 — and for x outside [−700, 700] or NaN, the lane takes detExp
// itself. Four groups of four lanes side by side, so that their chains of multiply-adds overlap.
inline void detExpFloatBatch(const double* x, float* out, int n) {
  typedef double v4d __attribute__((vector_size(32)));
  typedef int64_t v4l __attribute__((vector_size(32)));
  typedef float v4f __attribute__((vector_size(16)));
  typedef int32_t v4i __attribute__((vector_size(16)));
  constexpr double kRound = 6755399441055744.0;  // 1.5·2^52
  constexpr int kGroups = 4;
  for (int start = 0; start < n; start += 4 * kGroups) {
    const int lanes = n - start < 4 * kGroups ? n - start : 4 * kGroups;
    v4d v[kGroups], r[kGroups], q[kGroups];
    v4l kBits[kGroups], regular[kGroups];
    loadLanes(x + start, lanes, 0.0, v);
    for (int g = 0; g < kGroups; ++g) {
      regular[g] = (v[g] == v[g]) & (v[g] <= 700.0) & (v[g] >= -700.0);
      const v4d inRange = regular[g] ? v[g] : v4d{};
      const v4d shifted = inRange * kLog2E + kRound;
      const v4d k = shifted - kRound;
      kBits[g] = (v4l)shifted - (v4l)(v4d{} + kRound);
      r[g] = detExpRemainder(inRange, k);
    }
    for (int g = 0; g < kGroups; ++g) q[g] = detExpTaylor13(r[g]);  // inlined: the groups' chains interleave
    float result[4 * kGroups];
    int decided[4 * kGroups];
    for (int g = 0; g < kGroups; ++g) {
      const v4d y = q[g] * (v4d)((kBits[g] + 1023) << 52);
      const v4f lo = __builtin_convertvector(y * (1.0 - 0x1p-40), v4f);
      const v4f hi = __builtin_convertvector(y * (1.0 + 0x1p-40), v4f);
      const v4i same = ((v4i)lo == (v4i)hi) & __builtin_convertvector(regular[g], v4i);
      std::memcpy(result + 4 * g, &lo, sizeof lo);
      std::memcpy(decided + 4 * g, &same, sizeof same);
    }
    for (int i = 0; i < lanes; ++i) out[start + i] = decided[i] ? result[i] : float(detExp(x[start + i]));
  }
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

// detLog of n arguments in vector lanes, each lane taking detLog's operations in its order (so
// the same bits). Four groups of four lanes at a time, so that their chains of 17 dependent
// multiply-adds overlap (one group's chain alone left the core waiting). Normal positive
// arguments are reduced in the lanes, frexp built from the bits: x = f·2^(E − 1023) with
// f in [1, 2) gives frexp's m = f/2 in [0.5, 1) (the mantissa under the biased exponent 1022) and
// exponent E − 1022, exact, and the exponent as a double by the 2^52 trick (exact below 2^52).
// Zero, subnormal, negative, infinite and NaN arguments take detLogReduce one at a time.
//
// A batch whose arguments are all one value (one bit pattern: a material's constant alpha, say)
// takes detLog once; a pure function of the bits, so the same bits as each alone.
inline void detLogBatch(const double* x, double* out, int n) {
  typedef double v4d __attribute__((vector_size(32)));
  typedef int64_t v4l __attribute__((vector_size(32)));
  if (n > 1 && allSameBits(x, n)) {
    const double r = detLog(x[0]);
    for (int i = 0; i < n; ++i) out[i] = r;
    return;
  }
  constexpr int kGroups = 4;
  constexpr double kMinNormal = 2.2250738585072014e-308, kTwo52 = 4503599627370496.0;
  for (int start = 0; start < n; start += 4 * kGroups) {
    const int lanes = n - start < 4 * kGroups ? n - start : 4 * kGroups;
    v4d v[kGroups], s[kGroups], e[kGroups], r[kGroups];
    v4l regular[kGroups];
    loadLanes(x + start, lanes, 1.0, v);  // lanes past n: any regular value
    for (int g = 0; g < kGroups; ++g) {
      regular[g] = (v[g] >= kMinNormal) & (v[g] <= 1.7976931348623157e308);  // false for NaN
      const v4l bits = (v4l)(regular[g] ? v[g] : v4d{} + 1.0);
      v4d m = (v4d)((bits & 0x000fffffffffffffLL) | (int64_t(1022) << 52));
      v4d exponent = (v4d)(((bits >> 52) & 0x7ff) | (v4l)(v4d{} + kTwo52)) - kTwo52 - 1022.0;
      const v4l low = m < 0.70710678118654752440;
      m = low ? m * 2.0 : m;
      exponent = low ? exponent - 1.0 : exponent;
      s[g] = (m - 1.0) / (m + 1.0);
      e[g] = exponent;
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
