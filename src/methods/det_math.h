// exp and log in plain double arithmetic (+, −, ×, ÷ only), so a method's shader math gives the
// same bits on every machine: C libraries choose among exp/log implementations by CPU (e.g.
// glibc's FMA variants), and GPUs use their own approximations anyway. Accurate to a few double
// ulps (the test checks 4e-16 relative against libm), then rounded once to fp32 by the caller.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace oitref::methods {

// e^x: x = k·ln2 + r with |r| ≤ ln2/2, then a Taylor polynomial of r to degree 16.
inline double detExp(double x) {
  if (std::isnan(x)) return x;
  if (x > 709.0) return std::numeric_limits<double>::infinity();
  if (x < -745.0) return 0.0;
  constexpr double kLn2Hi = 0.693147180369123816490, kLn2Lo = 1.90821492927058770002e-10;
  const double k = std::nearbyint(x * 1.44269504088896338700);
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;
  double p = 1.0;
  for (int n = 16; n >= 1; --n) p = 1.0 + p * r / n;  // Horner form of Σ r^n / n!
  return std::ldexp(p, int(k));
}

// detExp of n arguments in vector lanes, eight groups of four side by side: each lane takes
// detExp's operations in its order (so the same bits); what changes is that 32 chains of 16
// dependent divisions overlap, which is most of detExp's time (one group at a time, each chain
// waited on its divisions' latency: MBOIT's accumulation pass on dense 960×540 took 530 ms for
// 13 M fragments with four lanes, 475 with 32). The steps around them are lane operations too, each
// giving what detExp's call gives for the arguments it reaches (the others take detExp itself):
//   nearbyint(v), |v| < 2^51 in the default rounding mode: (v + 1.5·2^52) − 1.5·2^52, whose sum
//     holds k in its low mantissa bits (round half to even, as nearbyint);
//   ldexp(p, k) = p·2^k rounded once: with 2^k built from its bits where it is normal (k ≥ −1022),
//     otherwise p·2^(k+64), exact because it is normal (p > ½, k ≥ −1075), then ·2^−64, which
//     rounds once into the subnormals as ldexp does.
inline void detExpBatch(const double* x, double* out, int n) {
  typedef double v4d __attribute__((vector_size(32)));
  typedef int64_t v4l __attribute__((vector_size(32)));
  constexpr double kLn2Hi = 0.693147180369123816490, kLn2Lo = 1.90821492927058770002e-10;
  constexpr double kRound = 6755399441055744.0;  // 1.5·2^52
  constexpr int kGroups = 8;  // chains side by side, so that their divisions overlap
  for (int start = 0; start < n; start += 4 * kGroups) {
    const int lanes = n - start < 4 * kGroups ? n - start : 4 * kGroups;
    v4d v[kGroups] = {}, k[kGroups], r[kGroups], p[kGroups];
    v4l kBits[kGroups];
    for (int i = 0; i < lanes; ++i) v[i / 4][i % 4] = x[start + i];
    for (int g = 0; g < kGroups; ++g) {
      // Lanes out of detExp's range (and unused ones, 0) are computed and then replaced below.
      const v4l regular = (v[g] == v[g]) & (v[g] <= 709.0) & (v[g] >= -745.0);
      const v4d inRange = regular ? v[g] : v4d{};
      const v4d shifted = inRange * 1.44269504088896338700 + kRound;
      k[g] = shifted - kRound;
      kBits[g] = (v4l)shifted - (v4l)(v4d{} + kRound);
      r[g] = (inRange - k[g] * kLn2Hi) - k[g] * kLn2Lo;
      p[g] = v4d{1.0, 1.0, 1.0, 1.0};
    }
    for (int m = 16; m >= 1; --m)
      for (int g = 0; g < kGroups; ++g) p[g] = 1.0 + p[g] * r[g] / double(m);
    double result[4 * kGroups];
    for (int g = 0; g < kGroups; ++g) {
      const v4l low = kBits[g] < -1022;
      const v4d scaled = p[g] * (v4d)(((low ? kBits[g] + 64 : kBits[g]) + 1023) << 52);
      const v4d y = low ? scaled * 0x1p-64 : scaled;
      std::memcpy(result + 4 * g, &y, sizeof y);
    }
    for (int i = 0; i < lanes; ++i) {
      const double xi = x[start + i];
      out[start + i] = std::isnan(xi) || xi > 709.0 || xi < -745.0 ? detExp(xi) : result[i];
    }
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
  constexpr double kLn2Hi = 0.693147180369123816490, kLn2Lo = 1.90821492927058770002e-10;
  return (2.0 * s * series + e * kLn2Lo) + e * kLn2Hi;
}
inline double detLog(double x) {
  double s = 0.0, e = 0.0, special = 0.0;
  return detLogReduce(x, s, e, special) ? detLogSeries(s, e) : special;
}

// detLog of n arguments, four at a time in vector lanes: each lane takes detLog's operations in
// its order (so the same bits); the four chains of 17 dependent multiply-adds overlap.
inline void detLogBatch(const double* x, double* out, int n) {
  typedef double v4d __attribute__((vector_size(32)));
  for (int start = 0; start < n; start += 4) {
    const int lanes = n - start < 4 ? n - start : 4;
    v4d s{}, e{};
    double special[4] = {};
    bool regular[4] = {};
    for (int i = 0; i < lanes; ++i) {
      double si = 0.0, ei = 0.0;
      regular[i] = detLogReduce(x[start + i], si, ei, special[i]);
      s[i] = si, e[i] = ei;
    }
    const v4d r = detLogSeries(s, e);
    for (int i = 0; i < lanes; ++i) out[start + i] = regular[i] ? r[i] : special[i];
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
