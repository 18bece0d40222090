// Moment-based OIT's moment sets, storage and reconstruction (moment_math.cpp, mboit.cpp, mt.cpp)
// against hand-derived cases and an independent reconstruction in long double: Gaussian
// elimination instead of Cholesky, roots by bisection between the derivative's roots (power) or
// Newton from points on the unit circle (trigonometric) instead of Newton–deflation and
// Aberth–Ehrlich, Lagrange instead of Newton interpolation.
#include <catch2/catch.hpp>

#include <array>
#include <bit>
#include <complex>
#include <random>
#include <functional>
#include <vector>

#include "method_fixture.h"
#include "methods/moment_math.h"
#include "support.h"

using namespace oitref;
using namespace oitref::test;
namespace mm = oitref::methods;

namespace {

using LD = long double;
using CLD = std::complex<long double>;
constexpr LD kPi = 3.141592653589793238462643383279502884L;
constexpr LD kZoneAngle = 0.1L * kPi;

template <typename T>
bool gaussSolve(std::vector<std::vector<T>> a, std::vector<T> rhs, std::vector<T>& x) {
  const size_t n = rhs.size();
  for (size_t col = 0; col < n; ++col) {
    size_t pivot = col;
    for (size_t r = col + 1; r < n; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    if (!(std::abs(a[pivot][col]) > 0)) return false;
    std::swap(a[pivot], a[col]);
    std::swap(rhs[pivot], rhs[col]);
    for (size_t r = col + 1; r < n; ++r) {
      const T f = a[r][col] / a[col][col];
      for (size_t k = col; k < n; ++k) a[r][k] -= f * a[col][k];
      rhs[r] -= f * rhs[col];
    }
  }
  x.assign(n, T(0));
  for (size_t i = n; i-- > 0;) {
    T s = rhs[i];
    for (size_t k = i + 1; k < n; ++k) s -= a[i][k] * x[k];
    x[i] = s / a[i][i];
  }
  return true;
}

LD evalPoly(const std::vector<LD>& c, LD x) {
  LD p = 0;
  for (size_t k = c.size(); k-- > 0;) p = p * x + c[k];
  return p;
}

// Real roots of a polynomial whose roots are all real and simple: the derivative's roots split
// the line into monotonic pieces; bisect each piece whose ends differ in sign.
std::vector<LD> bisectionRoots(const std::vector<LD>& c) {
  const size_t n = c.size() - 1;
  if (n == 0) return {};
  LD bound = 0;
  for (size_t k = 0; k < n; ++k) bound = std::max(bound, std::abs(c[k] / c[n]));
  bound += 1;
  std::vector<LD> d(n);
  for (size_t k = 1; k <= n; ++k) d[k - 1] = c[k] * LD(k);
  std::vector<LD> ends = {-bound};
  for (LD r : bisectionRoots(d)) ends.push_back(r);
  ends.push_back(bound);
  std::vector<LD> roots;
  for (size_t i = 0; i + 1 < ends.size(); ++i) {
    LD lo = ends[i], hi = ends[i + 1];
    LD flo = evalPoly(c, lo), fhi = evalPoly(c, hi);
    if (flo == 0) { roots.push_back(lo); continue; }
    if ((flo < 0) == (fhi < 0)) continue;
    for (int it = 0; it < 200; ++it) {
      const LD mid = (lo + hi) / 2, fm = evalPoly(c, mid);
      if ((fm < 0) == (flo < 0)) lo = mid, flo = fm;
      else hi = mid;
    }
    roots.push_back((lo + hi) / 2);
  }
  return roots;
}

// Roots on the unit circle: Newton in complex long double from 96 points on the circle; the
// distinct limits.
std::vector<CLD> circleRoots(const std::vector<CLD>& c) {
  const size_t n = c.size() - 1;
  std::vector<CLD> roots;
  for (int s = 0; s < 96 && roots.size() < n; ++s) {
    CLD x = std::polar(1.0L, 2 * kPi * (s + 0.5L) / 96);
    for (int it = 0; it < 200; ++it) {
      CLD p = 0, dp = 0;
      for (size_t k = n + 1; k-- > 0;) dp = dp * x + p, p = p * x + c[k];
      if (std::abs(dp) == 0) break;
      x -= p / dp;
    }
    CLD p = 0;
    for (size_t k = n + 1; k-- > 0;) p = p * x + c[k];
    if (!(std::abs(p) < 1e-12L * std::abs(c[n]))) continue;
    bool known = false;
    for (const CLD& r : roots) known = known || std::abs(r - x) < 1e-9L;
    if (!known) roots.push_back(x);
  }
  return roots;
}

LD circleParameter(CLD p) {
  LD r = std::abs(p.imag()) - std::abs(p.real());
  if (p.real() < 0) r = 2 - r;
  if (p.imag() < 0) r = 6 - r;
  return r;
}

// E[ℓ_i(X)] for the Lagrange basis at the points x, from the moments E[X^k] = mom[k].
template <typename T>
T lagrangeExpectation(const std::vector<T>& x, size_t i, const std::vector<T>& mom) {
  std::vector<T> poly = {T(1)};
  for (size_t j = 0; j < x.size(); ++j) {
    if (j == i) continue;
    std::vector<T> next(poly.size() + 1, T(0));
    for (size_t k = 0; k < poly.size(); ++k) {
      next[k + 1] += poly[k] / (x[i] - x[j]);
      next[k] -= poly[k] * x[j] / (x[i] - x[j]);
    }
    poly = next;
  }
  T e(0);
  for (size_t k = 0; k < poly.size(); ++k) e += poly[k] * mom[k];
  return e;
}

// Absorbance from normalised power moments b1…bN (unbiased); NaN when not reconstructible.
LD oraclePower(const std::vector<LD>& b, LD z, LD bias, const float* biasVector, LD overestimation) {
  const size_t count = b.size(), n = count / 2;
  std::vector<LD> m(count + 1);
  m[0] = 1;
  for (size_t k = 0; k < count; ++k) m[k + 1] = (1 - bias) * b[k] + bias * LD(biasVector[k]);
  std::vector<std::vector<LD>> h(n + 1, std::vector<LD>(n + 1));
  std::vector<LD> rhs(n + 1), c;
  for (size_t i = 0; i <= n; ++i) {
    for (size_t j = 0; j <= n; ++j) h[i][j] = m[i + j];
    rhs[i] = std::pow(z, LD(i));
  }
  if (!gaussSolve(h, rhs, c)) return NAN;
  const std::vector<LD> roots = bisectionRoots(c);
  if (roots.size() != n) return NAN;
  std::vector<LD> x = {z}, f = {overestimation};
  for (LD r : roots) x.push_back(r), f.push_back(r < z ? 1 : 0);
  LD a = 0;
  for (size_t i = 0; i < x.size(); ++i) a += f[i] * lagrangeExpectation(x, i, m);
  return a;
}

// Absorbance from normalised trigonometric moments (b1…bm complex, unbiased); NaN when not
// reconstructible.
LD oracleTrig(const std::vector<CLD>& b, LD z, LD bias, LD overestimation) {
  const size_t n = b.size();
  std::vector<CLD> B(n + 1);
  B[0] = 1;
  for (size_t k = 0; k < n; ++k) B[k + 1] = b[k] * (1 - bias);
  std::vector<std::vector<CLD>> t(n + 1, std::vector<CLD>(n + 1));
  std::vector<CLD> rhs(n + 1), c;
  const LD phaseScale = kPi - kZoneAngle / 2;
  const CLD w = std::polar(1.0L, (z + 1) * phaseScale);
  for (size_t i = 0; i <= n; ++i) {
    for (size_t j = 0; j <= n; ++j) t[i][j] = i >= j ? B[i - j] : std::conj(B[j - i]);
    rhs[i] = std::pow(w, LD(i));
  }
  if (!gaussSolve(t, rhs, c)) return NAN;
  std::vector<CLD> q(n + 1);
  for (size_t k = 0; k <= n; ++k) q[k] = std::conj(c[k]);
  const std::vector<CLD> roots = circleRoots(q);
  if (roots.size() != n) return NAN;
  const LD zoneBegin = circleParameter(std::polar(1.0L, 2 * kPi - kZoneAngle));
  const LD rampScale = 1 / (7 - zoneBegin), rampOffset = 1 - 7 * rampScale;
  std::vector<CLD> x = {w};
  std::vector<LD> f = {overestimation};
  for (const CLD& r : roots) {
    const LD p = circleParameter(r);
    x.push_back(r);
    f.push_back((p < circleParameter(w) ? 1 : 0) + std::clamp(p * rampScale + rampOffset, 0.0L, 1.0L));
  }
  LD a = 0;
  for (size_t i = 0; i < x.size(); ++i) a += f[i] * lagrangeExpectation(x, i, B).real();
  return a;
}

// Normalised moments of atoms (depth z_i, absorbance A_i) in a moment set.
std::vector<float> atomMoments(const mm::MomentSet& set, const std::vector<double>& z, const std::vector<double>& a) {
  std::vector<float> b(size_t(set.reals()));
  double total = 0;
  for (double ai : a) total += ai;
  const LD phaseScale = kPi - kZoneAngle / 2;
  for (int k = 0; k < set.reals(); ++k) {
    LD s = 0;
    for (size_t i = 0; i < z.size(); ++i) {
      if (!set.trigonometric) s += a[i] * std::pow(LD(z[i]), LD(k + 1));
      else {
        const CLD w = std::polar(1.0L, LD(k / 2 + 1) * (z[i] + 1) * phaseScale);
        s += a[i] * (k % 2 ? w.imag() : w.real());
      }
    }
    b[size_t(k)] = float(s / total);
  }
  return b;
}

float reconstruct(const mm::MomentSet& set, const std::vector<float>& b, float z, float bias, bool* fellBack = nullptr) {
  const mm::WrappingZone zone = mm::WrappingZone::fromAngle(float(kZoneAngle));
  return set.trigonometric ? mm::trigMomentAbsorbance(set.count, b.data(), z, bias, 0.0f, zone, fellBack)
                           : mm::powerMomentAbsorbance(set.count, b.data(), z, bias, mm::powerBiasVector(set.count, false), 0.0f, fellBack);
}

const char* kSets[] = {"power4", "power6", "power8", "trig2", "trig3", "trig4"};

}  // namespace

TEST_CASE("moments: the quantisation tables invert and map point masses into [0, 1]", "[moments]") {
  for (const char* name : kSets) {
    const mm::MomentSet set = mm::MomentSet::parse(name);
    INFO(name);
    float worstOutside = 0, worstRoundTrip = 0;
    for (int i = 0; i <= 400; ++i) {
      const double z = -1.0 + i / 200.0;
      const std::vector<float> b = atomMoments(set, {z}, {1.0});
      std::vector<float> q(b.size()), back(b.size());
      mm::quantiseMoments(set, b.data(), q.data());
      mm::offsetQuantised(set, q.data(), 1.0f);
      mm::dequantiseMoments(set, q.data(), back.data());
      for (size_t k = 0; k < b.size(); ++k) {
        worstOutside = std::max({worstOutside, -q[k], q[k] - 1.0f});
        worstRoundTrip = std::max(worstRoundTrip, std::abs(back[k] - b[k]));
      }
    }
    // The published tables carry 9–15 digits: their products are the identity to ~1e-9, and a
    // point mass at ±1 lands on the edge of [0, 1] to within that.
    CHECK(worstOutside <= 2e-6f);
    CHECK(worstRoundTrip <= 2e-5f);
  }
}

TEST_CASE("moments: the root finders against polynomials with known roots", "[moments]") {
  // (x + 0.8)(x + 0.1)(x − 0.4)(x − 0.95) = x⁴ − e1·x³ + e2·x² − e3·x + e4 with, by hand,
  // e1 = 0.45, e2 = 0.08 − 0.32 − 0.76 − 0.04 − 0.095 + 0.38 = −0.755,
  // e3 = 0.032 + 0.076 − 0.304 − 0.038 = −0.234, e4 = 0.0304.
  const double quartic[5] = {0.0304, 0.234, -0.755, -0.45, 1.0};
  const auto r = mm::realRootsOfRealRooted(quartic, 4);
  REQUIRE(r.size() == 4);
  const double want[4] = {-0.8, -0.1, 0.4, 0.95};
  for (int i = 0; i < 4; ++i) CHECK(r[size_t(i)] == Approx(want[i]).margin(1e-12));
  // (x − e^{0.3i})(x − e^{2i})(x − e^{4i}): roots on the unit circle, as MBOIT's are.
  const std::complex<double> a = std::polar(1.0, 0.3), b = std::polar(1.0, 2.0), c = std::polar(1.0, 4.0);
  const std::complex<double> cubic[4] = {-a * b * c, a * b + a * c + b * c, -(a + b + c), 1.0};
  const auto z = mm::complexRoots(cubic, 3);
  for (const auto& w : {a, b, c}) {
    double nearest = 1;
    for (const auto& x : z) nearest = std::min(nearest, std::abs(x - w));
    CHECK(nearest < 1e-12);
  }
}

TEST_CASE("moments: the real root finder in four lanes gives the one-at-a-time bits", "[moments]") {
  // realRootsOfRealRooted4 runs up to four polynomials' Newton stages side by side, each lane
  // frozen when its own iteration stops; realRootsOfRealRooted is the oracle, bit for bit. The
  // polynomials: random real roots in [−1, 1] (MBOIT's case), repeated and nearly repeated roots,
  // random coefficients (complex roots: NaN pairs), huge coefficients, a zero, NaN or infinite
  // leading coefficient (no roots), in groups of one to four.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), coefficient(-3.0, 3.0);
  int compared = 0;
  for (int n = 1; n <= 4; ++n)
    for (int group = 0; group < 200; ++group) {
      const int count = 1 + group % 4;
      std::array<std::array<double, 5>, 4> polys{};
      for (int l = 0; l < count; ++l) {
        std::array<double, 5>& c = polys[size_t(l)];
        const int kind = int(random() % 6);
        if (kind == 0) {
          for (int k = 0; k <= n; ++k) c[size_t(k)] = coefficient(random);
        } else {
          double roots[4];
          for (int i = 0; i < n; ++i) roots[i] = unit(random);
          if (kind == 1 && n > 1) roots[1] = roots[0];
          if (kind == 2 && n > 1) roots[1] = roots[0] + 1e-9;
          c = {1.0};  // Π (x − r_i), expanded
          for (int i = 0; i < n; ++i) {
            for (int k = i + 1; k >= 1; --k) c[size_t(k)] = c[size_t(k - 1)] - roots[i] * c[size_t(k)];
            c[0] = -roots[i] * c[0];
          }
          const double scale = kind == 3 ? 1e30 : kind == 4 ? -0.37 : 1.0;
          for (int k = 0; k <= n; ++k) c[size_t(k)] *= scale;
          if (kind == 5) c[size_t(group % n)] = group % 2 ? NAN : -INFINITY;  // a lower coefficient not finite
        }
        if (group % 37 == 5) c[size_t(n)] = l == 0 ? 0.0 : l == 1 ? NAN : INFINITY;
      }
      const double* pointers[4] = {polys[0].data(), polys[1].data(), polys[2].data(), polys[3].data()};
      mm::RootList<double> lanes[4];
      mm::realRootsOfRealRooted4(pointers, n, count, lanes);
      for (int l = 0; l < count; ++l) {
        const mm::RootList<double> one = mm::realRootsOfRealRooted(pointers[l], n);
        INFO("degree " << n << " group " << group << " lane " << l);
        REQUIRE(lanes[l].size() == one.size());
        for (size_t i = 0; i < one.size(); ++i)
          CHECK(std::bit_cast<uint64_t>(lanes[l][i]) == std::bit_cast<uint64_t>(one[i]));
        ++compared;
      }
    }
  CHECK(compared == 4 * (50 * (1 + 2 + 3 + 4)));
}

TEST_CASE("moments: the lane root finder and trig batch give the one-at-a-time bits", "[moments]") {
  // complexRootsBatch runs four polynomials in vector lanes, refilling a lane when its own
  // converges; complexRoots (scalar) is the oracle, bit for bit. The polynomials: random roots on
  // the unit circle (MBOIT's case), repeated roots (the ones that use all 500 sweeps), random
  // coefficients, and a zero or NaN leading coefficient (NaN roots).
  std::mt19937 random(7);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586), coefficient(-2.0, 2.0);
  for (int n = 1; n <= 4; ++n) {
    std::vector<std::array<std::complex<double>, 5>> polys;
    for (int p = 0; p < 61; ++p) {
      std::array<std::complex<double>, 5> c{};
      if (p % 5 == 3) {
        for (int k = 0; k <= n; ++k) c[size_t(k)] = {coefficient(random), coefficient(random)};
      } else {
        std::complex<double> roots[4];
        for (int i = 0; i < n; ++i) roots[i] = std::polar(1.0, angle(random));
        if (p % 5 == 1 && n > 1) roots[1] = roots[0];  // a double root
        c[0] = 1.0;  // Π (x − r_i), expanded
        for (int i = 0; i < n; ++i) {
          for (int k = i + 1; k >= 1; --k) c[size_t(k)] = c[size_t(k - 1)] - roots[i] * c[size_t(k)];
          c[0] = -roots[i] * c[0];
        }
        for (int k = 0; k <= n; ++k) c[size_t(k)] = (p % 2 ? -1.0 : 1.0) * c[size_t(k)];
      }
      if (p == 17) c[size_t(n)] = 0.0;
      if (p == 29) c[size_t(n)] = {NAN, 0.0};
      polys.push_back(c);
    }
    std::vector<const std::complex<double>*> pointers;
    for (const auto& c : polys) pointers.push_back(c.data());
    std::vector<std::complex<double>> batch(polys.size() * 4);
    mm::complexRootsBatch(pointers.data(), n, int(polys.size()), batch.data());
    int differing = 0;
    for (size_t p = 0; p < polys.size(); ++p) {
      const auto one = mm::complexRoots(polys[p].data(), n);
      for (int i = 0; i < n; ++i) {
        const std::complex<double> a = one[size_t(i)], b = batch[p * 4 + size_t(i)];
        const bool same = (std::bit_cast<uint64_t>(a.real()) == std::bit_cast<uint64_t>(b.real()) &&
                           std::bit_cast<uint64_t>(a.imag()) == std::bit_cast<uint64_t>(b.imag())) ||
                          (std::isnan(a.real()) && std::isnan(b.real()));
        differing += !same;
      }
    }
    INFO("degree " << n);
    CHECK(differing == 0);
  }
  // The trig reconstruction of a batch against one fragment at a time, on moments of random
  // layer sets (some of which fall back).
  for (const char* name : {"trig2", "trig3", "trig4"}) {
    const mm::MomentSet set = mm::MomentSet::parse(name);
    const mm::WrappingZone zone = mm::WrappingZone::fromAngle(0.1f * 3.14159265f);
    std::uniform_real_distribution<double> depth(-1.0, 1.0), alpha(0.05, 0.9);
    const int fragments = 45;
    std::vector<float> b, z;
    for (int f = 0; f < fragments; ++f) {
      std::vector<double> zs, as;
      for (int l = 0; l < 1 + f % 5; ++l) zs.push_back(f % 7 == 2 ? 0.25 : depth(random)), as.push_back(alpha(random));
      const std::vector<float> m = atomMoments(set, zs, as);
      b.insert(b.end(), m.begin(), m.end());
      z.push_back(float(depth(random)));
    }
    std::vector<float> batch(fragments);
    bool fell[fragments];
    mm::trigMomentAbsorbanceBatch(set.count, b.data(), z.data(), fragments, 5e-7f, 0.25f, zone, batch.data(), fell);
    int differing = 0, fallbacks = 0;
    for (int f = 0; f < fragments; ++f) {
      bool one = false;
      const float a = mm::trigMomentAbsorbance(set.count, b.data() + size_t(f) * size_t(set.reals()), z[size_t(f)],
                                               5e-7f, 0.25f, zone, &one);
      differing += std::bit_cast<uint32_t>(a) != std::bit_cast<uint32_t>(batch[size_t(f)]) || one != fell[f];
      fallbacks += one;
    }
    INFO(name << ": " << fallbacks << " of " << fragments << " fell back");
    CHECK(differing == 0);
  }
}

TEST_CASE("moments: N power or N/2 trigonometric moments reconstruct N/2 layers exactly", "[moments]") {
  // Atoms at well separated depths; with overestimation 0 the absorbance in front of a depth
  // between atoms is the share of the absorbance of the atoms in front (hand-derived: the
  // reconstruction is exact when the distribution has at most N/2 atoms). β = 1e-6 keeps the
  // matrices just positive definite; fp32 moments leave a few 1e-4.
  const std::vector<double> z = {-0.6, -0.1, 0.5, 0.85}, a = {0.5, 1.0, 0.7, 0.3};
  for (const char* name : kSets) {
    const mm::MomentSet set = mm::MomentSet::parse(name);
    const size_t atoms = size_t(set.trigonometric ? set.count : set.count / 2);
    const std::vector<double> zs(z.begin(), z.begin() + std::ptrdiff_t(atoms)), as(a.begin(), a.begin() + std::ptrdiff_t(atoms));
    const std::vector<float> b = atomMoments(set, zs, as);
    double total = 0;
    for (double x : as) total += x;
    for (size_t gap = 0; gap <= atoms; ++gap) {
      const double lo = gap == 0 ? -1.0 : zs[gap - 1], hi = gap == atoms ? 1.0 : zs[gap];
      const float query = float((lo + hi) / 2);
      double inFront = 0;
      for (size_t i = 0; i < gap; ++i) inFront += as[i];
      bool fellBack = true;
      const float got = reconstruct(set, b, query, 1e-6f, &fellBack);
      INFO(name << " at " << query << ": got " << got << ", want " << inFront / total);
      CHECK_FALSE(fellBack);
      CHECK(got == Approx(inFront / total).margin(2e-3));
    }
  }
}

TEST_CASE("moments: the fp32 reconstruction against the long-double oracle on random distributions", "[moments]") {
  // Five to eight atoms spread over [−0.95, 0.95], the published β: the fp32 reconstruction is
  // compared with the same biased moments reconstructed in long double. Far from rank
  // deficiency (atoms 0.15 apart at least) fp32 keeps the absorbance to 1e-4.
  test::BitStream rng(31);
  for (const char* name : kSets) {
    const mm::MomentSet set = mm::MomentSet::parse(name);
    const float bias = set.defaultBias(false);
    double worst = 0;
    int compared = 0;
    for (int trial = 0; trial < 300; ++trial) {
      std::vector<double> z, a;
      const int atoms = 5 + int(rng.next() % 4);
      while (int(z.size()) < atoms) {
        const double c = double(rng.uniform(-0.95f, 0.95f));
        bool apart = true;
        for (double o : z) apart = apart && std::abs(o - c) >= 0.15;
        if (apart) z.push_back(c), a.push_back(double(rng.uniform(0.05f, 2.0f)));
      }
      const std::vector<float> b = atomMoments(set, z, a);
      const float query = rng.uniform(-1.0f, 1.0f);
      bool fellBack = false;
      const float got = reconstruct(set, b, query, bias, &fellBack);
      LD want;
      if (set.trigonometric) {
        std::vector<CLD> bc;
        for (int k = 0; k < set.count; ++k) bc.emplace_back(b[size_t(2 * k)], b[size_t(2 * k + 1)]);
        want = oracleTrig(bc, query, bias, 0);
      } else {
        want = oraclePower(std::vector<LD>(b.begin(), b.end()), query, bias, mm::powerBiasVector(set.count, false), 0);
      }
      if (std::isnan(double(want)) || fellBack) continue;
      worst = std::max(worst, std::abs(double(got) - double(want)));
      ++compared;
    }
    INFO(name << ": worst |fp32 − long double| " << worst << " over " << compared << " queries");
    CHECK(compared > 250);
    CHECK(worst < 1e-4);  // measured: 4e-7 (power4) … 1.3e-5 (power8)
  }
}

namespace {

// MBOIT's composite over a pixel's fragments in long double (eq. 2.9 with the oracle
// reconstruction), the moment sums scaled by (1 + e_k). NaN when a reconstruction fails.
glm::dvec3 mboitClosedForm(const mm::MomentSet& set, const std::vector<TransparentFragment>& f, glm::dvec3 c0,
                           const std::function<LD(const TransparentFragment&)>& warped, LD bias, LD overestimation,
                           const std::vector<LD>& e) {
  const int reals = set.reals();
  std::vector<LD> sums(size_t(reals) + 1, 0), zs;
  const LD phaseScale = kPi - kZoneAngle / 2;
  for (const auto& fr : f) {
    const LD a = -std::log(1.0L - std::min<LD>(fr.color.a, 1.0L - 0x1p-20L)), z = warped(fr);
    zs.push_back(z);
    if (a < 1e-7L) continue;
    sums[0] += a;
    for (int k = 0; k < reals; ++k) {
      if (!set.trigonometric) sums[size_t(k) + 1] += a * std::pow(z, LD(k + 1));
      else {
        const CLD w = std::polar(1.0L, LD(k / 2 + 1) * (z + 1) * phaseScale);
        sums[size_t(k) + 1] += a * (k % 2 ? w.imag() : w.real());
      }
    }
  }
  for (size_t k = 0; k < sums.size(); ++k) sums[k] *= 1 + e[k % e.size()];
  glm::dvec3 acc(0.0);
  LD accA = 0, reveal = 1;
  for (size_t i = 0; i < f.size(); ++i) {
    LD w = 1;
    if (sums[0] >= 0.00100050033L) {
      LD a;
      if (set.trigonometric) {
        std::vector<CLD> b;
        for (int k = 0; k < set.count; ++k) b.emplace_back(sums[size_t(2 * k + 1)] / sums[0], sums[size_t(2 * k + 2)] / sums[0]);
        a = oracleTrig(b, zs[i], bias, overestimation);
      } else {
        std::vector<LD> b;
        for (int k = 1; k <= reals; ++k) b.push_back(sums[size_t(k)] / sums[0]);
        a = oraclePower(b, zs[i], bias, mm::powerBiasVector(set.count, false), overestimation);
      }
      if (std::isnan(double(a))) return glm::dvec3(NAN);
      w = std::exp(-sums[0] * a);
      if (!set.trigonometric) w = std::clamp(w, 0.0L, 1.0L);
    }
    acc += glm::dvec3(glm::vec3(f[i].color)) * double(f[i].color.a * w);
    accA += f[i].color.a * w;
    reveal *= 1 - f[i].color.a;
  }
  return acc / double(std::clamp<LD>(accA, 1e-4L, 5e4L)) * double(1 - reveal) + c0 * double(reveal);
}

}  // namespace

TEST_CASE("mboit: every moment set is eq. 2.9 with the long-double reconstruction", "[moments][mboit]") {
  // warp=log, pixels whose layers are at least 0.05 apart in warped depth (closer layers make
  // the matrices so ill-conditioned that fp32 moments decide the answer). The bound is how far
  // the closed form moves when the moment sums change by a few fp32 ulps.
  const Camera& cam = reference().scene.camera;
  auto warped = [&](const TransparentFragment& fr) {
    return 2.0L * std::log((long double)fr.viewDepth / cam.nearPlane) / std::log((long double)cam.farPlane / cam.nearPlane) - 1.0L;
  };
  for (const char* name : {"power6", "power8", "trig2", "trig3", "trig4"}) {
    const mm::MomentSet set = mm::MomentSet::parse(name);
    const FrameResult frame = render(reference().scene, "mboit", {{"warp", "log"}, {"moments", name}});
    const LD bias = set.defaultBias(false), over = 0.25L;
    int compared = 0, skipped = 0;
    double worstShare = 0;
    forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
      if (f.empty()) return;
      for (size_t i = 0; i < f.size(); ++i)
        for (size_t j = i + 1; j < f.size(); ++j)
          if (std::abs(warped(f[i]) - warped(f[j])) < 0.05L) return;
      const glm::dvec3 want = mboitClosedForm(set, f, c0, warped, bias, over, {0});
      if (std::isnan(want.x)) return void(++skipped);
      const LD u = (f.size() + 2) * 0x1p-24L;
      double sensitivity = 0;
      for (int trial = 0; trial < 8; ++trial) {
        std::vector<LD> e;
        for (int k = 0; k < 9; ++k) e.push_back(((trial >> (k % 3)) & 1 ? u : -u) * (k % 2 ? 1 : -1));
        const glm::dvec3 moved = mboitClosedForm(set, f, c0, warped, bias, over, e);
        for (int k = 0; k < 3; ++k) sensitivity = std::max(sensitivity, std::abs(moved[k] - want[k]));
      }
      const double bound = 4 * sensitivity + 1e-5;
      const glm::vec4 got = frame.finalFloat.fetch(x, y);
      for (int k = 0; k < 3; ++k) {
        const double err = std::abs(double(got[k]) - want[k]);
        worstShare = std::max(worstShare, err / bound);
        if (err > bound)
          FAIL(name << " pixel " << x << "," << y << " channel " << k << " (" << f.size() << " layers): got " << got[k]
                    << ", closed form " << want[k] << ", bound " << bound);
      }
      ++compared;
    });
    INFO(name << ": worst error " << worstShare << " of the bound over " << compared << " pixels, " << skipped << " not reconstructible");
    CHECK(compared > 250);
    CHECK(skipped == 0);
  }
}

TEST_CASE("mboit storage=unorm16: the stored moments are the normalised moments, quantised", "[moments][mboit]") {
  // Four full-screen layers updated one after another in raster order: what is stored must
  // dequantise to the layers' normalised moments (closed form in long double), up to one
  // rounding to 1/65535 per update in quantised space, amplified by the dequantisation matrix
  // (its largest row sum of magnitudes is below 3.4 for every set).
  Scene s = layerScene(8, {0.1f, 0.2f, 0.3f});
  const float zs[4] = {0.0f, -1.5f, -4.0f, 0.8f}, alphas[4] = {0.3f, 0.6f, 0.45f, 0.2f};
  for (int i = 0; i < 4; ++i) s.objects.push_back(quad({0, 0, zs[i]}, 40, {0.9f, 0.5f, 0.1f, alphas[i]}));
  const FrameResult truth = render(s, "abuffer", {{"lists", "keep"}});
  const auto stored = truth.fragmentLists.at(4, 4);
  const std::vector<TransparentFragment> f(stored.begin(), stored.end());
  REQUIRE(f.size() == 4);
  const Camera& cam = s.camera;
  for (const char* name : kSets) {
    const mm::MomentSet set = mm::MomentSet::parse(name);
    const FrameResult frame = render(s, "mboit", {{"moments", name}, {"storage", "unorm16"}, {"warp", "log"}});
    auto image = [&](const std::string& n) -> const Image* {
      for (const auto& [k, img] : frame.dump)
        if (k == n) return &img;
      return nullptr;
    };
    REQUIRE(image("moments"));
    CHECK(image("moments")->format().name() == (set.reals() >= 4 ? "rgba16" : "rg16"));
    std::vector<double> z, a;
    double total = 0;
    for (const auto& fr : f) {
      z.push_back(double(2.0L * std::log((LD)fr.viewDepth / cam.nearPlane) / std::log((LD)cam.farPlane / cam.nearPlane) - 1.0L));
      a.push_back(-std::log(1.0 - double(fr.color.a)));
      total += a.back();
    }
    const std::vector<float> want = atomMoments(set, z, a);
    float stored[8] = {}, got[8] = {};
    const glm::vec4 lo = image("moments")->fetch(4, 4);
    const glm::vec4 hi = image("moments_more") ? image("moments_more")->fetch(4, 4) : glm::vec4(0.0f);
    for (int k = 0; k < set.reals(); ++k) stored[k] = k < 4 ? lo[k] : hi[k - 4];
    for (int k = 0; k < set.reals(); ++k) CHECK(stored[k] * 65535.0f == Approx(std::round(stored[k] * 65535.0f)).margin(1e-3));
    mm::dequantiseMoments(set, stored, got);
    INFO(name);
    CHECK(image("b0")->fetch(4, 4).r == Approx(total).epsilon(1e-6));
    for (int k = 0; k < set.reals(); ++k) CHECK(got[k] == Approx(want[size_t(k)]).margin(3.4 * 4 * 0.5 / 65535 + 1e-6));
  }
}

TEST_CASE("mt: Sharpe's moment transparency is the MSM bound on log depth in closed form", "[moments][mt]") {
  // u = ln(v/near)/ln(far/near); A = −ln(1 − min(α, 1 − 0.5/256)); the four-moment bound with the
  // root weights 1 in front and 0 at u (overestimation 0), clamped to [0, 1], β = 3e-7 towards
  // (0, 0.375, 0, 0.375); w = exp(−ΣA · bound); composited as WBOIT. Pixels whose layers are at
  // least 0.025 apart in u, as the MBOIT tests (u spans half the range of MBOIT's depth).
  const Camera& cam = reference().scene.camera;
  const LD range = std::log((LD)cam.farPlane / cam.nearPlane);
  auto unit = [&](const TransparentFragment& fr) { return std::log((LD)fr.viewDepth / cam.nearPlane) / range; };
  const FrameResult mt = render(reference().scene, "mt");
  auto closedForm = [&](const std::vector<TransparentFragment>& f, glm::dvec3 c0, LD e) {
    LD sums[5] = {0, 0, 0, 0, 0};
    for (const auto& fr : f) {
      const LD a = -std::log(1.0L - std::min<LD>(fr.color.a, 1.0L - 0.5L / 256)), u = unit(fr);
      for (int k = 0; k <= 4; ++k) sums[k] += a * std::pow(u, LD(k)) * (1 + (k % 2 ? e : -e));
    }
    glm::dvec3 acc(0.0);
    LD accA = 0, reveal = 1;
    for (const auto& fr : f) {
      std::vector<LD> b;
      for (int k = 1; k <= 4; ++k) b.push_back(sums[0] != 0 ? sums[k] / sums[0] : sums[k]);
      const LD bound = std::clamp(oraclePower(b, unit(fr), 3e-7L, mm::powerBiasVector(4, false), 0), 0.0L, 1.0L);
      const LD w = std::exp(-bound * sums[0]);
      acc += glm::dvec3(glm::vec3(fr.color)) * double(fr.color.a * w);
      accA += fr.color.a * w;
      reveal *= 1 - fr.color.a;
    }
    return acc / double(std::clamp<LD>(accA, 1e-4L, 5e4L)) * double(1 - reveal) + c0 * double(reveal);
  };
  int compared = 0;
  forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
    if (f.empty()) return;
    for (size_t i = 0; i < f.size(); ++i)
      for (size_t j = i + 1; j < f.size(); ++j)
        if (std::abs(unit(f[i]) - unit(f[j])) < 0.025L) return;
    const glm::dvec3 want = closedForm(f, c0, 0);
    if (std::isnan(want.x)) return;
    const LD u = (f.size() + 2) * 0x1p-24L;
    double sensitivity = 0;
    for (LD e : {u, -u}) {
      const glm::dvec3 moved = closedForm(f, c0, e);
      for (int k = 0; k < 3; ++k) sensitivity = std::max(sensitivity, std::abs(moved[k] - want[k]));
    }
    requireClose(mt.finalFloat, x, y, want, 4 * sensitivity + 1e-5, "mt");
    ++compared;
  });
  CHECK(compared > 250);
  // By hand: opaque red (α = 1) in front of green at α = 0.5. The α clamp gives red
  // A1 = −ln(0.5/256); four moments reconstruct two layers exactly, so red's bound is 0 (w = 1)
  // and green's is A1/(A1 + A2), w = exp(−A1) = 0.5/256. Revealage 0: the colour is
  // (red + 0.5·w·green) / (1 + 0.5·w).
  Scene s = layerScene(8, {0, 0, 1});
  s.objects = {quad({0, 0, 0}, 10, {1, 0, 0, 1}), quad({0, 0, -1}, 10, {0, 1, 0, 0.5f})};
  s.objects[0].transparentOverride = true;  // α = 1 but drawn with the transparent objects
  const double w = 0.5 / 256, norm = 1 + 0.5 * w;
  requireClose(render(s, "mt").finalFloat, 4, 4, {1 / norm, 0.5 * w / norm, 0}, 2e-5, "mt, opaque front layer");
}

TEST_CASE("moments: the batched reconstruction gives powerMomentAbsorbance's bits and fallbacks", "[moments]") {
  // powerMomentAbsorbanceBatch runs the four-moment closed form eight fragments at a time in
  // lanes; every lane must equal the one-fragment function, including where it falls back
  // (singular Hankel matrices, non-finite moments) and for counts not a multiple of eight.
  test::BitStream rng(31);
  for (int count : {4, 6, 8})
  for (int n : {8 * 61 + 1, 8 * 61 + 5, 8 * 61 + 7}) {  // the last group: one, five, seven fragments
    std::vector<float> b(static_cast<size_t>(n * count)), z(static_cast<size_t>(n)), batch(static_cast<size_t>(n));
    std::vector<char> fellBackBatch(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      const int kind = int(rng.next() % 4);
      // Moments of one to three layers (valid or on the boundary), random numbers, or specials.
      float depths[3] = {rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f)};
      float weights[3] = {rng.uniform(0.0f, 1.0f), rng.uniform(0.0f, 1.0f), rng.uniform(0.0f, 1.0f)};
      const int layers = 1 + int(rng.next() % 3);
      float total = 0.0f;
      for (int l = 0; l < layers; ++l) total += weights[l];
      for (int k = 0; k < count; ++k) {
        float m = 0.0f;
        for (int l = 0; l < layers; ++l) m += weights[l] / total * std::pow(depths[l], float(k + 1));
        b[size_t(i * count + k)] = kind == 0   ? m
                                   : kind == 1 ? rng.uniform(-1.0f, 1.0f)
                                   : kind == 2 ? (rng.next() % 2 ? NAN : INFINITY)
                                               : m + rng.uniform(-1e-4f, 1e-4f);
      }
      z[size_t(i)] = rng.next() % 5 == 0 ? depths[0] : rng.uniform(-1.0f, 1.0f);
    }
    for (float bias : {0.0f, 5e-7f, 3e-2f})
    for (float overestimation : {0.25f, 0.0f}) {  // MBOIT's default; moment transparency's
      const float* biasVector = methods::powerBiasVector(count, false);
      static_assert(sizeof(bool) == sizeof(char));
      methods::powerMomentAbsorbanceBatch(count, b.data(), z.data(), n, bias, biasVector, overestimation, batch.data(),
                                          reinterpret_cast<bool*>(fellBackBatch.data()));
      int fallbacks = 0, different = 0;
      for (int i = 0; i < n; ++i) {
        bool fellBack = false;
        const float one = methods::powerMomentAbsorbance(count, &b[size_t(i * count)], z[size_t(i)], bias, biasVector,
                                                         overestimation, &fellBack);
        fallbacks += fellBack;
        different += test::toBits(one) != test::toBits(batch[size_t(i)]) || fellBack != bool(fellBackBatch[size_t(i)]);
      }
      INFO("count " << count << " n " << n << " bias " << bias << " overestimation " << overestimation << " fallbacks " << fallbacks);
      CHECK(different == 0);
      CHECK(fallbacks > 0);
      CHECK(fallbacks < n);
    }
  }
}
