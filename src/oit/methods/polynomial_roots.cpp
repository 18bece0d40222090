// Roots of the polynomials of degree ≤ 4 that MBOIT's reconstruction needs: real roots of a
// real-rooted polynomial (power moments) and complex roots (trigonometric moments), by
// deterministic iterations in double, one polynomial at a time (the oracle) and in vector lanes.
#include "methods/polynomial_roots.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "methods/moment_lanes.h"

namespace oitref::methods {

namespace {
// Ascending, by insertion (what std::sort does for so few; a NaN pair sends the caller to its
// fallback whatever its place).
void sortAscending(RootList<double>& roots) {
  for (int i = 1; i < roots.count; ++i) {
    const double v = roots.values[i];
    int k = i;
    for (; k > 0 && v < roots.values[k - 1]; --k) roots.values[k] = roots.values[k - 1];
    roots.values[k] = v;
  }
}
}  // namespace

namespace {

inline double absF(double x) { return std::fabs(x); }
inline lanes::d4 absF(lanes::d4 x) {  // the sign bits cleared
  const lanes::d4 negativeZero = {-0.0, -0.0, -0.0, -0.0};
  return (lanes::d4)((d4Mask)x & ~(d4Mask)negativeZero);
}

// The largest root of the monic real-rooted polynomial with lower coefficients a (degree d):
// Newton's method from above it, 1 + max |a_k|, which decreases monotonically to the root (the
// polynomial is convex and increasing beyond it), until an iterate no longer decreases (or the
// derivative is 0, or 500 steps). On lanes, each lane stops on its own and keeps its value.
template <typename T>
T newtonFromAbove(const T* a, int d, MaskOf<T> active) {
  T bound = T{} + 0.0;
  for (int k = 0; k < d; ++k) {
    const T v = absF(a[k]);
    bound = selectF(bound < v, v, bound);  // std::max(bound, v)
  }
  T x = 1.0 + bound;
  for (int it = 0; it < 500 && anyLane(active); ++it) {
    T p = T{} + 1.0, dp = T{} + 0.0;
    for (int k = d - 1; k >= 0; --k) dp = dp * x + p, p = p * x + a[k];
    const T next = x - p / dp;
    active = lanes::both(active, lanes::both(dp != 0.0, next < x));
    x = selectF(active, next, x);
  }
  return x;
}

// a(x) = (x − r)·q(x): a becomes q, by synthetic division, highest first.
template <typename T>
void deflate(T* a, int d, T r) {
  T q[5], carry = T{} + 1.0;
  for (int k = d - 1; k >= 0; --k) {
    q[k] = carry;
    carry = a[k] + carry * r;
  }
  for (int k = 0; k < d; ++k) a[k] = q[k];
}

// What is left after the Newton stages, degree 1 or 2 (monic, lower coefficients a0, a1): the
// root, or both roots by the quadratic formula in its cancellation-free form (NaN when the
// discriminant is negative); then all of them ascending.
void lastRoots(int degree, double a0, double a1, RootList<double>& roots) {
  if (degree == 1) roots.push_back(-a0);
  if (degree == 2) {
    const double h = 0.5 * a1, disc = h * h - a0;
    if (!(disc >= 0.0)) {
      roots.push_back(NAN), roots.push_back(NAN);
    } else {
      const double s = h >= 0.0 ? -h - std::sqrt(disc) : -h + std::sqrt(disc);  // the larger |root|
      roots.push_back(s);
      roots.push_back(s != 0.0 ? a0 / s : 0.0);
    }
  }
  sortAscending(roots);
}

}  // namespace

// Newton stages (newtonFromAbove) and deflation down to degree 2, then lastRoots.
RootList<double> realRootsOfRealRooted(const double* c, int n) {
  RootList<double> roots;
  if (!(c[n] != 0.0) || !std::isfinite(c[n])) return roots;
  double a[5];
  for (int k = 0; k <= n; ++k) a[k] = c[k] / c[n];
  for (int d = n; d >= 3; --d) {
    const double x = newtonFromAbove(a, d, true);
    roots.push_back(x);
    deflate(a, d, x);
  }
  lastRoots(std::min(n, 2), a[0], a[1], roots);
  return roots;
}

// The same for up to four polynomials of one degree side by side: each Newton stage runs until
// every lane has stopped, a stopped lane frozen; the last roots per lane.
void realRootsOfRealRooted4(const double* const* c, int n, int count, RootList<double>* out) {
  using lanes::d4;
  d4 a[5] = {};
  d4Mask valid{};
  for (int l = 0; l < count; ++l) {
    out[l] = {};
    const double lead = c[l][n];
    if (!(lead != 0.0) || !std::isfinite(lead)) continue;
    valid[l] = -1;
    for (int k = 0; k <= n; ++k) a[k][l] = c[l][k] / lead;
  }
  for (int d = n; d >= 3; --d) {
    const d4 x = newtonFromAbove(a, d, valid);
    for (int l = 0; l < count; ++l)
      if (valid[l]) out[l].push_back(x[l]);
    deflate(a, d, x);
  }
  for (int l = 0; l < count; ++l)
    if (valid[l]) lastRoots(std::min(n, 2), a[0][l], a[1][l], out[l]);
}

namespace {

// Aberth–Ehrlich iteration from the points (0.4 + 0.9i)^k, in place (each update uses the newest
// others): z_i −= w / (1 − w·Σ_{j≠i} 1/(z_i − z_j)) with w = p(z_i)/p'(z_i), until no root moves
// by more than 1e-15 of 1 + its size, or 500 sweeps. Cubically convergent for simple roots, which
// matters here: MBOIT's roots crowd together when layers do.
constexpr int kAberthSweeps = 500;
template <typename T>
void aberthStart(int n, Cx<T>* z) {
  Cd start{1.0, 0.0};
  for (int i = 0; i < n; ++i, start = start * Cd{0.4, 0.9}) z[i] = {T{} + start.x, T{} + start.y};
}
// One sweep over the roots z of the monic polynomial with lower coefficients a; whether a root
// moved. On lanes, every lane runs its own polynomial's sweep (a root whose p(z) is exactly 0
// stays), and only the `active` lanes change.
template <typename T>
MaskOf<T> aberthSweep(const Cx<T>* a, int n, MaskOf<T> active, Cx<T>* z) {
  const Cx<T> one{T{} + 1.0, T{} + 0.0};
  MaskOf<T> moved{};
  for (int i = 0; i < n; ++i) {
    const Cx<T> x = z[i];
    Cx<T> p = one, dp{T{} + 0.0, T{} + 0.0};
    for (int k = n - 1; k >= 0; --k) dp = dp * x + p, p = p * x + a[k];
    Cx<T> repulsion{T{} + 0.0, T{} + 0.0};
    for (int j = 0; j < n; ++j)
      if (j != i) repulsion = repulsion + divide(one, x - z[j]);
    const Cx<T> w = divide(p, dp);
    const Cx<T> step = divide(w, one - w * repulsion);
    const MaskOf<T> update = lanes::both(active, lanes::negate(lanes::both(p.x == 0.0, p.y == 0.0)));
    z[i] = {selectF(update, x.x - step.x, x.x), selectF(update, x.y - step.y, x.y)};
    const T size = 1.0 + sqrtF(norm(x));
    moved = lanes::either(moved, lanes::both(update, lanes::negate(norm(step) <= 1e-30 * size * size)));
  }
  return moved;
}

// The monic form of Σ c_k x^k: false when the leading coefficient is 0 or not finite.
bool monic(const std::complex<double>* c, int n, Cd* a) {
  const Cd lead{c[n].real(), c[n].imag()};
  if (!(norm(lead) > 0.0) || !std::isfinite(norm(lead))) return false;
  for (int k = 0; k <= n; ++k) a[k] = divide(Cd{c[k].real(), c[k].imag()}, lead);
  return true;
}

}  // namespace

RootList<std::complex<double>> complexRoots(const std::complex<double>* c, int n) {
  RootList<std::complex<double>> out;
  for (int i = 0; i < n; ++i) out.push_back(std::complex<double>(NAN, NAN));
  Cd a[5], z[4];
  if (!monic(c, n, a)) return out;
  aberthStart(n, z);
  for (int sweep = 0; sweep < kAberthSweeps; ++sweep)
    if (!aberthSweep<double>(a, n, true, z)) break;
  for (int i = 0; i < n; ++i) out.values[i] = {z[i].x, z[i].y};
  return out;
}

void complexRootsBatch(const std::complex<double>* const* c, int n, int count, std::complex<double>* roots) {
  // Four lanes, each taking the next polynomial when its own has converged (or used its 500
  // sweeps): a few polynomials take all 500 (roots that coincide converge only linearly), and
  // lanes that waited for them would run no faster than one polynomial at a time.
  //
  // Those few also cost most of the time (in dense.json's trig3 accumulate pass, 0.8 % of the
  // polynomials made 42 % of the sweeps), and nearly all of them end in an exact cycle: a state
  // of the roots, bit for bit, that recurs after p sweeps (found on average by sweep 15, p ≈ 7).
  // A sweep is a function of the lane's state alone, so from there on the states repeat with
  // period p, every sweep moves (as every one before did), and the state after sweep 500 is the
  // one a multiple of p earlier: the lane stops after (500 − t) mod p more sweeps, with the bits
  // 500 would give. A cycle is found by comparing each state with the one saved at the last
  // power-of-two sweep (Brent's method: by sweep 2·max(start, p)). complexRoots, the oracle of
  // the tests, runs every sweep.
  using lanes::d4;
  Cx<d4> a[5], z[4];
  MaskOf<d4> active{};
  int problem[4] = {-1, -1, -1, -1}, sweeps[4] = {}, limit[4] = {};
  Cd saved[4][4];  // [lane][root]: the state after the last power-of-two sweep
  int next = 0;
  Cd start[4];
  aberthStart(n, start);
  auto load = [&](int l) {
    problem[l] = -1;
    active[l] = 0;
    while (next < count) {
      const int p = next++;
      Cd m[5];
      if (!monic(c[p], n, m)) {
        for (int i = 0; i < n; ++i) roots[size_t(p) * 4 + size_t(i)] = {NAN, NAN};
        continue;
      }
      for (int k = 0; k <= n; ++k) a[k].x[l] = m[k].x, a[k].y[l] = m[k].y;
      for (int i = 0; i < n; ++i) z[i].x[l] = start[i].x, z[i].y[l] = start[i].y;
      problem[l] = p, sweeps[l] = 0, limit[l] = kAberthSweeps, active[l] = -1;
      return;
    }
  };
  auto sameBits = [](double u, double v) { return std::bit_cast<uint64_t>(u) == std::bit_cast<uint64_t>(v); };
  // After sweep t = sweeps[l], every one of which moved: detect a cycle, or save at powers of two.
  auto watchForCycle = [&](int l) {
    const int t = sweeps[l];
    if (limit[l] != kAberthSweeps) return;  // the end is known already
    bool same = t > 1;
    for (int i = 0; i < n && same; ++i) same = sameBits(z[i].x[l], saved[l][i].x) && sameBits(z[i].y[l], saved[l][i].y);
    if (same) {
      const int period = t - (1 << std::bit_width(unsigned(t - 1)) >> 1);  // since the save at 2^⌊log2(t − 1)⌋
      limit[l] = t + (kAberthSweeps - t) % period;
    } else if ((t & (t - 1)) == 0) {
      for (int i = 0; i < n; ++i) saved[l][i] = {z[i].x[l], z[i].y[l]};
    }
  };
  for (int l = 0; l < 4; ++l) load(l);
  while (anyLane(active)) {
    const MaskOf<d4> moved = aberthSweep<d4>(a, n, active, z);
    for (int l = 0; l < 4; ++l) {
      if (!active[l]) continue;
      if (moved[l] && ++sweeps[l] < limit[l]) {
        watchForCycle(l);
        if (sweeps[l] < limit[l]) continue;
      }
      for (int i = 0; i < n; ++i) roots[size_t(problem[l]) * 4 + size_t(i)] = {z[i].x[l], z[i].y[l]};
      load(l);
    }
  }
}

}  // namespace oitref::methods
