// Moment generation and the reconstruction of the absorbance from power and
// trigonometric moments (Münstermann, Krumpen, Klein, Peters, "Moment-Based Order-Independent
// Transparency", 2018). The linear algebra runs in fp32 in the order a shader runs it: that is
// where MBOIT's precision is decided (Cholesky pivots of nearly singular Hankel matrices). The
// polynomial roots are found by deterministic iterations in double instead of the paper code's
// fp32 closed forms (Blinn's cubic, Neumark's quartic), which need atan2/cos; the roots differ
// from a GPU's by rounding only.
#include "methods/moment_math.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "methods/det_math.h"
#include "methods/moment_lanes.h"
#include "oitref/core/lanes.h"

namespace oitref::methods {

MomentSet MomentSet::parse(const std::string& name) {
  for (const MomentSet s : {MomentSet{false, 4}, MomentSet{false, 6}, MomentSet{false, 8}, MomentSet{true, 2},
                            MomentSet{true, 3}, MomentSet{true, 4}})
    if (s.name() == name) return s;
  throw std::invalid_argument("moments '" + name + "' is not one of power4, power6, power8, trig2, trig3, trig4");
}

std::string MomentSet::name() const { return (trigonometric ? "trig" : "power") + std::to_string(count); }

float MomentSet::defaultBias(bool quantised) const {
  if (trigonometric) return count == 2 ? (quantised ? 4e-4f : 4e-7f) : count == 3 ? (quantised ? 6.5e-4f : 8e-7f)
                                                                                  : (quantised ? 8.5e-4f : 1.5e-6f);
  return count == 4 ? (quantised ? 6e-5f : 5e-7f) : count == 6 ? (quantised ? 6e-4f : 5e-6f) : (quantised ? 2.5e-3f : 5e-5f);
}

float circleToParameter(float x, float y) {
  float result = std::fabs(y) - std::fabs(x);
  result = x < 0.0f ? 2.0f - result : result;
  return y < 0.0f ? 6.0f - result : result;
}

WrappingZone WrappingZone::fromAngle(float angle) {
  constexpr double kPi = 3.14159265358979323846;
  WrappingZone z;
  z.angle = angle;
  z.phaseScale = float(kPi - 0.5 * double(angle));
  if (angle > 0.0f) {
    const SinCos begin = detSinCos(2.0 * kPi - double(angle));
    const float zoneBegin = circleToParameter(float(begin.cos), float(begin.sin)), zoneEnd = 7.0f;
    z.rampScale = 1.0f / (zoneEnd - zoneBegin);
    z.rampOffset = 1.0f - zoneEnd * z.rampScale;
  }
  return z;
}

namespace {

Cf unitCirclePoint(float z, const WrappingZone& zone) {
  const float phase = z * zone.phaseScale + zone.phaseScale;
  const SinCos sc = detSinCos(double(phase));
  return {float(sc.cos), float(sc.sin)};
}

// w, w², w³, w⁴ formed as the shaders do: w² = w·w, w³ = w·w², w⁴ = w²·w².
void circlePowers(Cf w, int count, Cf* out) {
  out[0] = w;
  if (count > 1) out[1] = w * w;
  if (count > 2) out[2] = w * out[1];
  if (count > 3) out[3] = out[1] * out[1];
}

}  // namespace

void momentsOf(const MomentSet& set, float z, const WrappingZone& zone, float* out) {
  if (set.trigonometric) {
    Cf w[4];
    circlePowers(unitCirclePoint(z, zone), set.count, w);
    for (int k = 0; k < set.count; ++k) out[2 * k] = w[k].x, out[2 * k + 1] = w[k].y;
    return;
  }
  const PowerMoments p(z);
  const float powers[8] = {p.z, p.z2, p.z3, p.z4, p.z5, p.z6, p.z7, p.z8};
  for (int k = 0; k < set.count; ++k) out[k] = powers[k];
}

namespace {

// 4 power moments in closed form, in the order of the paper code's fp32 operations; `ok` is
// false where the moments cannot be used (a pivot not positive, a root not finite), and the
// result there is `overestimation`.
template <typename F>
F fourPowerMomentAbsorbance(const F* m, F z, float overestimation, MaskOf<F>& ok) {
  // Cholesky of [1 m0 m1; m0 m1 m2; m1 m2 m3] = L·D·Lᵀ.
  const F d11 = m[1] - m[0] * m[0];
  const F l21d11 = m[2] - m[0] * m[1];
  const MaskOf<F> pivot1 = d11 > splatF<F>(0.0f);
  const F l21 = l21d11 / d11;
  const F d22 = (m[3] - m[1] * m[1]) - l21d11 * l21;
  const MaskOf<F> pivot2 = d22 > splatF<F>(0.0f);
  // Solve L·D·Lᵀ·c = (1, z, z²).
  F c0 = splatF<F>(1.0f), c1 = z - m[0], c2 = z * z - m[1] - l21 * c1;
  c1 = c1 / d11;
  c2 = c2 / d22;
  c1 = c1 - l21 * c2;
  c0 = c0 - (c1 * m[0] + c2 * m[1]);
  // Roots of c0 + c1·x + c2·x².
  const F p = c1 / c2, q = c0 / c2;
  const F disc = p * p * 0.25f - q;
  const F r = sqrtF(disc);
  const F z1 = -p * 0.5f - r, z2 = -p * 0.5f + r;
  ok = lanes::both(lanes::both(pivot1, pivot2), lanes::both(finiteF(z1), finiteF(z2)));
  // Newton form of the quadratic through (z, f0), (z1, f1), (z2, f2).
  const F one = splatF<F>(1.0f), zero = splatF<F>(0.0f);
  const F f0 = splatF<F>(overestimation), f1 = selectF(z1 < z, one, zero), f2 = selectF(z2 < z, one, zero);
  const F f01 = (f1 - f0) / (z1 - z);
  const F f12 = (f2 - f1) / (z2 - z1);
  const F f012 = (f12 - f01) / (z2 - z);
  // p(x) = f0 + f01·(x − z) + f012·(x − z)(x − z1) = a0 + a1·x + a2·x².
  const F a2 = f012;
  const F a1 = f01 - f012 * (z + z1);
  const F a0 = f0 - f01 * z + f012 * z * z1;
  return selectF(ok, a0 + a1 * m[0] + a2 * m[1], f0);
}

float divideAny(float a, float b) { return a / b; }
v8f divideAny(v8f a, v8f b) { return a / b; }
Cf divideAny(Cf a, Cf b) { return divide(a, b); }
// A real value f as a T: itself, or f + 0i.
template <typename T, typename R>
T valueOf(R f) {
  if constexpr (std::is_same_v<T, Cf>) return Cf{f, 0.0f};
  else return f;
}

// Newton's divided differences through (x_i, f_i), i = 0…n, expanded to monomial coefficients.
template <typename T, typename R>
void interpolate(const T* x, const R* f, int n, T* poly) {
  T dd[5];
  for (int i = 0; i <= n; ++i) dd[i] = valueOf<T>(f[i]);
  for (int level = 1; level <= n; ++level)
    for (int i = n; i >= level; --i) dd[i] = divideAny(dd[i] - dd[i - 1], x[i] - x[i - level]);
  // Horner on the Newton form: poly = dd[n]; poly = poly·(t − x_i) + dd[i].
  for (int k = 0; k <= n; ++k) poly[k] = T{};
  poly[0] = dd[n];
  for (int i = n - 1; i >= 0; --i) {
    for (int k = n - i; k >= 1; --k) poly[k] = poly[k - 1] - poly[k] * x[i];
    poly[0] = dd[i] - poly[0] * x[i];
  }
}

}  // namespace

namespace {

// A fragment's reconstruction from 6 or 8 power moments up to its roots, for one fragment
// (F = float) or eight side by side (F = v8f: each lane the scalar operations, so the same bits).
// m[1…count] hold the biased moments on entry; m[0] = 1 is set here. c gets the polynomial whose
// real roots are wanted (fp32, as the shader's solve leaves it). False (per lane) where the
// Hankel matrix is not positive definite: the fragment falls back.
template <typename F>
MaskOf<F> powerProblem(int count, F z, F* m, F* c) {
  m[0] = splatF<F>(1.0f);
  const int n = count / 2;
  MaskOf<F> ok = splatF<F>(0.0f) == splatF<F>(0.0f);
  // Hankel matrix H_ij = m_{i+j} = L·D·Lᵀ.
  F L[5][5] = {}, D[5];
  for (int j = 0; j <= n; ++j) {
    F d = m[2 * j];
    for (int k = 0; k < j; ++k) d = d - L[j][k] * L[j][k] * D[k];
    ok = lanes::both(ok, d > splatF<F>(0.0f));
    if (!anyLane(ok)) return ok;
    D[j] = d;
    for (int i = j + 1; i <= n; ++i) {
      F v = m[i + j];
      for (int k = 0; k < j; ++k) v = v - L[i][k] * L[j][k] * D[k];
      L[i][j] = v / d;
    }
  }
  // H·c = (1, z, …, z^n): forward, scale, backward substitution.
  c[0] = splatF<F>(1.0f);
  for (int k = 1; k <= n; ++k) c[k] = c[k - 1] * z;
  for (int i = 1; i <= n; ++i)
    for (int k = 0; k < i; ++k) c[i] = c[i] - L[i][k] * c[k];
  for (int i = 0; i <= n; ++i) c[i] = c[i] / D[i];
  for (int i = n - 1; i >= 0; --i)
    for (int k = i + 1; k <= n; ++k) c[i] = c[i] - L[k][i] * c[k];
  return ok;
}

// The rest, from the n roots x (as fp32; per lane): the absorbance. `ok` turns false where a root
// or the result is not finite.
template <typename F>
F powerAbsorbanceFromRoots(const F* m, int n, const F* roots, F z, float overestimation, MaskOf<F>& ok) {
  F x[5], f[5];
  x[0] = z, f[0] = splatF<F>(overestimation);
  for (int i = 0; i < n; ++i) {
    x[i + 1] = roots[i];
    ok = lanes::both(ok, finiteF(x[i + 1]));
    f[i + 1] = selectF(x[i + 1] < z, splatF<F>(1.0f), splatF<F>(0.0f));
  }
  F poly[5];
  interpolate(x, f, n, poly);
  F absorbance = splatF<F>(0.0f);
  for (int k = 0; k <= n; ++k) absorbance = absorbance + poly[k] * m[k];
  ok = lanes::both(ok, finiteF(absorbance));
  return absorbance;
}

}  // namespace

float powerMomentAbsorbance(int count, const float* b, float z, float bias, const float* biasVector, float overestimation,
                            bool* fellBack) {
  if (fellBack) *fellBack = false;
  auto fallBack = [&] {
    if (fellBack) *fellBack = true;
    return overestimation;
  };
  if (count == 4) {
    float m[4];
    for (int k = 0; k < 4; ++k) m[k] = biasedMoment(b[k], bias, biasVector[k]);
    bool ok = true;
    const float a = fourPowerMomentAbsorbance(m, z, overestimation, ok);
    return ok && std::isfinite(a) ? a : fallBack();
  }
  float m[9], c[5];
  for (int k = 0; k < count; ++k) m[k + 1] = biasedMoment(b[k], bias, biasVector[k]);
  if (!powerProblem(count, z, m, c)) return fallBack();
  const int n = count / 2;
  double polynomial[5] = {};
  for (int k = 0; k <= n; ++k) polynomial[k] = c[k];
  const RootList<double> found = realRootsOfRealRooted(polynomial, n);
  if (int(found.size()) != n) return fallBack();
  float roots[4];
  for (int i = 0; i < n; ++i) roots[i] = float(found[size_t(i)]);
  bool ok = true;
  const float absorbance = powerAbsorbanceFromRoots(m, n, roots, z, overestimation, ok);
  return ok ? absorbance : fallBack();
}

void powerMomentAbsorbanceBatch(int count, const float* b, const float* z, int n, float bias, const float* biasVector,
                                float overestimation, float* absorbance, bool* fellBack) {
  int i = 0;
  if (count == 4) {
    typedef float v4f __attribute__((vector_size(16)));
    // Eight fragments: rows[4j + k] their moments, depths[j], results into out[j], fell[j].
    auto eight = [&](const float* rows, const float* depths, float* out, bool* fell) {
      auto row = [&](int j) {
        v4f r;
        std::memcpy(&r, rows + size_t(j) * 4, sizeof r);
        return r;
      };
      // Eight fragments' four moments turned into four vectors of eight lanes in registers (an
      // 8×4 transpose: pairs of rows, then the 4×4 transposes of both halves at once).
      const v8f a0 = __builtin_shufflevector(row(0), row(4), 0, 1, 2, 3, 4, 5, 6, 7);
      const v8f a1 = __builtin_shufflevector(row(1), row(5), 0, 1, 2, 3, 4, 5, 6, 7);
      const v8f a2 = __builtin_shufflevector(row(2), row(6), 0, 1, 2, 3, 4, 5, 6, 7);
      const v8f a3 = __builtin_shufflevector(row(3), row(7), 0, 1, 2, 3, 4, 5, 6, 7);
      const v8f t0 = __builtin_shufflevector(a0, a1, 0, 8, 1, 9, 4, 12, 5, 13);
      const v8f t1 = __builtin_shufflevector(a0, a1, 2, 10, 3, 11, 6, 14, 7, 15);
      const v8f t2 = __builtin_shufflevector(a2, a3, 0, 8, 1, 9, 4, 12, 5, 13);
      const v8f t3 = __builtin_shufflevector(a2, a3, 2, 10, 3, 11, 6, 14, 7, 15);
      const v8f column[4] = {__builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13),
                             __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15),
                             __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13),
                             __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15)};
      v8f m[4], zl;
      for (int k = 0; k < 4; ++k) m[k] = biasedMoment(column[k], bias, biasVector[k]);
      zl = lanes::loadEachLane<v8f>(depths);  // written a float at a time just before
      v8i ok;
      const v8f a = fourPowerMomentAbsorbance(m, zl, overestimation, ok);
      const v8i use = ok & finiteF(a);
      const v8f result = selectF(use, a, splatF<v8f>(overestimation));
      std::memcpy(out, &result, sizeof result);
      storeLaneFlags(~use, fell);
    };
    for (; i + 8 <= n; i += 8) eight(b + size_t(i) * 4, z + i, absorbance + i, fellBack + i);
    if (i < n) {
      // The last one to seven in lanes too, the lanes beyond them repeating the last fragment
      // (each lane's operations are its own: the same bits as one fragment alone).
      float rows[32], depths[8], out[8];
      bool fell[8];
      for (int l = 0; l < 8; ++l) {
        const int j = std::min(i + l, n - 1);
        std::memcpy(rows + 4 * l, b + size_t(j) * 4, 4 * sizeof(float));
        depths[l] = z[j];
      }
      eight(rows, depths, out, fell);
      for (int l = 0; i + l < n; ++l) absorbance[i + l] = out[l], fellBack[i + l] = fell[l];
      i = n;
    }
  }
  if (count != 4) {
    // 6 and 8 moments: eight fragments' problems and absorbances in lanes, their roots four at a
    // time (the Newton iterations are a chain of dependent divisions, which one fragment leaves
    // mostly idle). The lanes beyond the last fragment repeat it.
    const int roots = count / 2;
    for (; i < n; i += 8) {
      const int m = std::min(8, n - i);
      v8f moments[9], zl, c[5];
      for (int l = 0; l < 8; ++l) {
        const int j = i + std::min(l, m - 1);
        for (int k = 0; k < count; ++k) moments[k + 1][l] = biasedMoment(b[size_t(j) * count + size_t(k)], bias, biasVector[k]);
        zl[l] = z[j];
      }
      v8i ok = powerProblem(count, zl, moments, c);
      double polynomials[8][5];
      const double* solvablePolynomials[8];
      int solvable[8], s = 0;
      for (int l = 0; l < m; ++l)
        if (ok[l]) {
          for (int k = 0; k <= roots; ++k) polynomials[l][k] = c[k][l];
          solvablePolynomials[s] = polynomials[l], solvable[s++] = l;
        }
      RootList<double> found[8];
      for (int g = 0; g < s; g += 4) realRootsOfRealRooted4(solvablePolynomials + g, roots, std::min(4, s - g), found + g);
      v8f rootLanes[4] = {};
      v8i complete = {};
      for (int j = 0; j < s; ++j) {
        const int l = solvable[j];
        if (int(found[j].size()) != roots) continue;
        complete[l] = -1;
        for (int r = 0; r < roots; ++r) rootLanes[r][l] = float(found[j][size_t(r)]);
      }
      ok &= complete;
      const v8f a = powerAbsorbanceFromRoots(moments, roots, rootLanes, zl, overestimation, ok);
      for (int l = 0; l < m; ++l) absorbance[i + l] = ok[l] ? a[l] : overestimation, fellBack[i + l] = !ok[l];
    }
  }
  for (; i < n; ++i)
    absorbance[i] = powerMomentAbsorbance(count, b + size_t(i) * count, z[i], bias, biasVector, overestimation, &fellBack[i]);
}

namespace {

// A fragment's trigonometric reconstruction up to its roots: the biased moments, the point of
// its depth on the unit circle, and the polynomial whose roots are wanted (ok false: the
// Toeplitz matrix is not positive definite, the fragment falls back).
struct TrigProblem {
  Cf B[5];
  Cf w;
  std::complex<double> polynomial[5];
  bool ok = false;
};

TrigProblem trigProblem(int n, const float* b, float z, float bias, const WrappingZone& zone) {
  TrigProblem t;
  Cf* B = t.B;
  B[0] = {1.0f, 0.0f};
  for (int k = 1; k <= n; ++k) B[k] = Cf{b[2 * (k - 1)], b[2 * (k - 1) + 1]} * (1.0f - bias);
  // Toeplitz T_ij = b_{i−j} (i ≥ j), conj(b_{j−i}) above: T = L·D·Lᴴ.
  Cf L[5][5] = {};
  float D[5];
  for (int j = 0; j <= n; ++j) {
    float d = B[0].x;
    for (int k = 0; k < j; ++k) d -= norm(L[j][k]) * D[k];
    if (!(d > 0.0f)) return t;
    D[j] = d;
    const float inv = 1.0f / d;
    for (int i = j + 1; i <= n; ++i) {
      Cf v = B[i - j];
      for (int k = 0; k < j; ++k) v = v - L[i][k] * conj(L[j][k]) * D[k];
      L[i][j] = v * inv;
    }
  }
  t.w = unitCirclePoint(z, zone);
  Cf c[5];
  c[0] = {1.0f, 0.0f};
  circlePowers(t.w, n, c + 1);
  for (int i = 1; i <= n; ++i)
    for (int k = 0; k < i; ++k) c[i] = c[i] - L[i][k] * c[k];
  for (int i = 0; i <= n; ++i) c[i] = c[i] * (1.0f / D[i]);
  for (int i = n - 1; i >= 0; --i)
    for (int k = i + 1; k <= n; ++k) c[i] = c[i] - conj(L[k][i]) * c[k];
  // The roots of Σ conj(c_k)·x^k lie on the unit circle.
  for (int k = 0; k <= n; ++k) t.polynomial[k] = {double(c[k].x), -double(c[k].y)};
  t.ok = true;
  return t;
}

// The rest, from the roots: the absorbance, or false (fall back) where a root or the result is
// not finite.
bool trigAbsorbanceFromRoots(const TrigProblem& t, int n, const std::complex<double>* roots, float overestimation,
                             const WrappingZone& zone, float& absorbance) {
  const float depthParameter = circleToParameter(t.w.x, t.w.y);
  Cf x[5];
  float f[5];
  x[0] = t.w, f[0] = overestimation;
  for (int i = 0; i < n; ++i) {
    x[i + 1] = {float(roots[i].real()), float(roots[i].imag())};
    if (!std::isfinite(x[i + 1].x) || !std::isfinite(x[i + 1].y)) return false;
    const float rootParameter = circleToParameter(x[i + 1].x, x[i + 1].y);
    f[i + 1] = (rootParameter < depthParameter ? 1.0f : 0.0f) +
               std::clamp(rootParameter * zone.rampScale + zone.rampOffset, 0.0f, 1.0f);
  }
  Cf poly[5];
  interpolate(x, f, n, poly);
  absorbance = 0.0f;
  for (int k = 0; k <= n; ++k) absorbance += (t.B[k] * poly[k]).x;
  return std::isfinite(absorbance);
}

}  // namespace

float trigMomentAbsorbance(int count, const float* b, float z, float bias, float overestimation, const WrappingZone& zone,
                           bool* fellBack) {
  float absorbance = overestimation;
  trigMomentAbsorbanceBatch(count, b, &z, 1, bias, overestimation, zone, &absorbance, fellBack);
  return absorbance;
}

void trigMomentAbsorbanceBatch(int count, const float* b, const float* z, int n, float bias, float overestimation,
                               const WrappingZone& zone, float* absorbance, bool* fellBack) {
  const int reals = 2 * count;
  constexpr int kMost = 64;
  for (int start = 0; start < n; start += kMost) {
    const int m = std::min(kMost, n - start);
    TrigProblem problems[kMost];
    const std::complex<double>* polynomials[kMost];
    int solvable[kMost], s = 0;
    for (int i = 0; i < m; ++i) {
      problems[i] = trigProblem(count, b + size_t(start + i) * size_t(reals), z[start + i], bias, zone);
      if (problems[i].ok) polynomials[s] = problems[i].polynomial, solvable[s++] = i;
    }
    std::complex<double> roots[kMost * 4];
    if (s == 1) {  // complexRoots itself: trigMomentAbsorbance's path, the oracle of the lanes' tests
      const RootList<std::complex<double>> r = complexRoots(polynomials[0], count);
      for (int k = 0; k < count; ++k) roots[k] = r[size_t(k)];
    } else if (s > 1) {
      complexRootsBatch(polynomials, count, s, roots);
    }
    for (int i = 0; i < m; ++i) {
      float& out = absorbance[start + i];
      out = overestimation;
      if (fellBack) fellBack[start + i] = true;
    }
    for (int j = 0; j < s; ++j) {
      const int i = solvable[j];
      float& out = absorbance[start + i];
      const bool ok = trigAbsorbanceFromRoots(problems[i], count, roots + size_t(j) * 4, overestimation, zone, out);
      if (!ok) out = overestimation;
      if (fellBack) fellBack[start + i] = !ok;
    }
  }
}

}  // namespace oitref::methods
