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

namespace {
// |x| per lane (the sign bit cleared, as fabs).
float absLanes(float x) { return std::fabs(x); }
v8f absLanes(v8f x) { return (v8f)((v8i)x & 0x7fffffff); }
// std::clamp(x, 0, 1) per lane (NaN stays NaN).
float clampUnit(float x) { return std::clamp(x, 0.0f, 1.0f); }
v8f clampUnit(v8f x) {
  const v8f zero = splatF<v8f>(0.0f), one = splatF<v8f>(1.0f);
  return selectF(x < zero, zero, selectF(one < x, one, x));
}
template <typename F>
F circleParameter(F x, F y) {
  F result = absLanes(y) - absLanes(x);
  result = selectF(x < splatF<F>(0.0f), splatF<F>(2.0f) - result, result);
  return selectF(y < splatF<F>(0.0f), splatF<F>(6.0f) - result, result);
}
}  // namespace

float circleToParameter(float x, float y) { return circleParameter(x, y); }

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
template <typename T>
void circlePowers(Cx<T> w, int count, Cx<T>* out) {
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
template <typename F>
Cx<F> divideAny(Cx<F> a, Cx<F> b) { return divide(a, b); }
// A real value f as a T: itself, or f + 0i.
template <typename T, typename R>
T valueOf(R f) {
  if constexpr (std::is_same_v<T, R>) return f;
  else return T{f, splatF<R>(0.0f)};
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

// A fragment's trigonometric reconstruction up to its roots, for one fragment (F = float) or
// eight side by side (F = v8f: each lane the scalar operations, so the same bits). B[1…n] hold
// the biased moments on entry; B[0] = 1 is set here. w is the fragment's depth on the unit circle;
// c gets the coefficients whose conjugates, Σ conj(c_k)·x^k, form the polynomial with the wanted
// roots (on the unit circle). False (per lane) where the Toeplitz matrix is not positive definite:
// the fragment falls back.
template <typename F>
MaskOf<F> trigProblem(int n, Cx<F> w, Cx<F>* B, Cx<F>* c) {
  const F one = splatF<F>(1.0f), zero = splatF<F>(0.0f);
  B[0] = {one, zero};
  MaskOf<F> ok = zero == zero;
  // Toeplitz T_ij = b_{i−j} (i ≥ j), conj(b_{j−i}) above: T = L·D·Lᴴ.
  Cx<F> L[5][5] = {};
  F D[5];
  for (int j = 0; j <= n; ++j) {
    F d = B[0].x;
    for (int k = 0; k < j; ++k) d = d - norm(L[j][k]) * D[k];
    ok = lanes::both(ok, d > zero);
    if (!anyLane(ok)) return ok;
    D[j] = d;
    const F inv = one / d;
    for (int i = j + 1; i <= n; ++i) {
      Cx<F> v = B[i - j];
      for (int k = 0; k < j; ++k) v = v - L[i][k] * conj(L[j][k]) * D[k];
      L[i][j] = v * inv;
    }
  }
  c[0] = {one, zero};
  circlePowers(w, n, c + 1);
  for (int i = 1; i <= n; ++i)
    for (int k = 0; k < i; ++k) c[i] = c[i] - L[i][k] * c[k];
  for (int i = 0; i <= n; ++i) c[i] = c[i] * (one / D[i]);
  for (int i = n - 1; i >= 0; --i)
    for (int k = i + 1; k <= n; ++k) c[i] = c[i] - conj(L[k][i]) * c[k];
  return ok;
}

// The rest, from the n roots (as fp32; per lane): the absorbance. `ok` turns false where a root or
// the result is not finite.
template <typename F>
F trigAbsorbanceFromRoots(const Cx<F>* B, Cx<F> w, int n, const Cx<F>* roots, float overestimation,
                          const WrappingZone& zone, MaskOf<F>& ok) {
  const F depthParameter = circleParameter(w.x, w.y);
  Cx<F> x[5];
  F f[5];
  x[0] = w, f[0] = splatF<F>(overestimation);
  for (int i = 0; i < n; ++i) {
    x[i + 1] = roots[i];
    ok = lanes::both(ok, lanes::both(finiteF(x[i + 1].x), finiteF(x[i + 1].y)));
    const F rootParameter = circleParameter(x[i + 1].x, x[i + 1].y);
    f[i + 1] = selectF(rootParameter < depthParameter, splatF<F>(1.0f), splatF<F>(0.0f)) +
               clampUnit(rootParameter * zone.rampScale + zone.rampOffset);
  }
  Cx<F> poly[5];
  interpolate(x, f, n, poly);
  F absorbance = splatF<F>(0.0f);
  for (int k = 0; k <= n; ++k) absorbance = absorbance + (B[k] * poly[k]).x;
  ok = lanes::both(ok, finiteF(absorbance));
  return absorbance;
}

// A fragment's k-th trigonometric moment (k ≥ 1) from its stored reals, pulled towards 0.
Cf biasedTrigMoment(const float* b, int k, float bias) { return Cf{b[2 * (k - 1)], b[2 * (k - 1) + 1]} * (1.0f - bias); }

// The polynomial Σ conj(c_k)·x^k whose roots complexRoots finds.
void conjugatePolynomial(const Cf* c, int n, std::complex<double>* polynomial) {
  for (int k = 0; k <= n; ++k) polynomial[k] = {double(c[k].x), -double(c[k].y)};
}

}  // namespace

float trigMomentAbsorbance(int count, const float* b, float z, float bias, float overestimation, const WrappingZone& zone,
                           bool* fellBack) {
  Cf B[5], c[5];
  for (int k = 1; k <= count; ++k) B[k] = biasedTrigMoment(b, k, bias);
  const Cf w = unitCirclePoint(z, zone);
  bool ok = trigProblem(count, w, B, c);
  float absorbance = overestimation;
  if (ok) {
    std::complex<double> polynomial[5];
    conjugatePolynomial(c, count, polynomial);
    const RootList<std::complex<double>> found = complexRoots(polynomial, count);
    Cf roots[4];
    for (int k = 0; k < count; ++k) roots[k] = {float(found[size_t(k)].real()), float(found[size_t(k)].imag())};
    absorbance = trigAbsorbanceFromRoots(B, w, count, roots, overestimation, zone, ok);
    if (!ok) absorbance = overestimation;
  }
  if (fellBack) *fellBack = !ok;
  return absorbance;
}

void trigMomentAbsorbanceBatch(int count, const float* b, const float* z, int n, float bias, float overestimation,
                               const WrappingZone& zone, float* absorbance, bool* fellBack) {
  const int reals = 2 * count;
  // Eight fragments in lanes; the lanes beyond the last fragment repeat it.
  for (int i = 0; i < n; i += 8) {
    const int m = std::min(8, n - i);
    Cx<v8f> B[5], w, c[5];
    for (int l = 0; l < 8; ++l) {
      const int j = i + std::min(l, m - 1);
      const Cf point = unitCirclePoint(z[j], zone);
      w.x[l] = point.x, w.y[l] = point.y;
      for (int k = 1; k <= count; ++k) {
        const Cf moment = biasedTrigMoment(b + size_t(j) * reals, k, bias);
        B[k].x[l] = moment.x, B[k].y[l] = moment.y;
      }
    }
    v8i ok = trigProblem(count, w, B, c);
    std::complex<double> polynomials[8][5];
    const std::complex<double>* solvablePolynomials[8];
    int solvable[8], s = 0;
    for (int l = 0; l < m; ++l)
      if (ok[l]) {
        Cf lane[5];
        for (int k = 0; k <= count; ++k) lane[k] = {c[k].x[l], c[k].y[l]};
        conjugatePolynomial(lane, count, polynomials[l]);
        solvablePolynomials[s] = polynomials[l], solvable[s++] = l;
      }
    std::complex<double> roots[8 * 4];
    if (s > 0) complexRootsBatch(solvablePolynomials, count, s, roots);
    Cx<v8f> rootLanes[4] = {};
    for (int j = 0; j < s; ++j)
      for (int r = 0; r < count; ++r) {
        rootLanes[r].x[solvable[j]] = float(roots[size_t(j) * 4 + size_t(r)].real());
        rootLanes[r].y[solvable[j]] = float(roots[size_t(j) * 4 + size_t(r)].imag());
      }
    const v8f a = trigAbsorbanceFromRoots(B, w, count, rootLanes, overestimation, zone, ok);
    for (int l = 0; l < m; ++l) {
      absorbance[i + l] = ok[l] ? a[l] : overestimation;
      if (fellBack) fellBack[i + l] = !ok[l];
    }
  }
}

}  // namespace oitref::methods
