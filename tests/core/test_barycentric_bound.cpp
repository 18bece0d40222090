// FragmentStage::barycentricsBoundedOn, the proof over a rectangle of pixels that lets a flat
// triangle skip interpolation. Its claim is checked pixel by pixel: wherever it says yes, every
// pixel centre's B = |b0| + |b1| + |b2|, computed as interpolate() computes it (written out here
// in its order), is below FragmentStage::kFlatBarycentricBound.
#include <catch2/catch.hpp>

#include <cmath>

#include "pipeline/fragment_ops.h"
#include "pipeline/setup.h"
#include "support.h"

using namespace oitref;
using namespace oitref::detail;

namespace {

// The NDC map of a viewport of w × h pixels at the origin, as FragmentStage builds it.
struct Ndc {
  double map[4];
  Ndc(int w, int h) : map{2.0 / w, 0.5 * (2.0 / w) - 1.0, 2.0 / h, 0.5 * (2.0 / h) - 1.0} {}
};

// B at pixel centre (x, y): x_n, y_n, k_i = (I_i0·x_n + I_i1·y_n) + I_i2, w = 1/((k0 + k1) + k2),
// b_i = k_i·w, B = (|b0| + |b1|) + |b2|.
double computedB(const TriangleInterpolation& t, const Ndc& ndc, int x, int y) {
  const double xn = double(x) * ndc.map[0] + ndc.map[1], yn = double(y) * ndc.map[2] + ndc.map[3];
  double k[3];
  for (int i = 0; i < 3; ++i) k[i] = t.inverse[i][0] * xn + t.inverse[i][1] * yn + t.inverse[i][2];
  const double w = 1.0 / (k[0] + k[1] + k[2]);
  return (std::fabs(k[0] * w) + std::fabs(k[1] * w)) + std::fabs(k[2] * w);
}

// The window z at pixel centre (x, y) the long way, as interpolate() computes it: b_i = k_i·w,
// z = ½·((b0·c0 + b1·c1 + b2·c2)/w) + ½.
double computedWindowZ(const TriangleInterpolation& t, const Ndc& ndc, int x, int y) {
  const double xn = double(x) * ndc.map[0] + ndc.map[1], yn = double(y) * ndc.map[2] + ndc.map[3];
  double k[3];
  for (int i = 0; i < 3; ++i) k[i] = t.inverse[i][0] * xn + t.inverse[i][1] * yn + t.inverse[i][2];
  const double w = 1.0 / (k[0] + k[1] + k[2]);
  return 0.5 * ((k[0] * w * t.clipZ[0] + k[1] * w * t.clipZ[1] + k[2] * w * t.clipZ[2]) / w) + 0.5;
}

// Whether every centre of r has B below the bound (NaN is not below it).
bool allBelow(const TriangleInterpolation& t, const Ndc& ndc, const PixelRect& r) {
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x)
      if (!(computedB(t, ndc, x, y) < FragmentStage::kFlatBarycentricBound)) return false;
  return true;
}

}  // namespace

TEST_CASE("barycentric bound: where it proves B bounded on a rectangle, every pixel centre's B is below the bound", "[interp]") {
  const int w = 256, h = 192;
  const Ndc ndc(w, h);
  test::BitStream rng(97);
  int proven = 0, unproven = 0, unprovenAndOver = 0;
  for (int t = 0; t < 600; ++t) {
    glm::dvec4 v[3];
    for (auto& p : v) p = glm::dvec4(rng.uniform(-1.5f, 1.5f), rng.uniform(-1.5f, 1.5f), 0.0, rng.uniform(0.2f, 2.0f));
    if (t % 3 == 1) v[1].w = rng.uniform(-1.0f, 0.1f);  // a vertex behind the eye: a horizon in view
    if (t % 3 == 2) {                                     // nearly edge-on
      const double a = rng.uniform(0.2f, 0.8f);
      v[2] = v[0] * a + v[1] * (1.0 - a);
      v[2].x += rng.uniform(-1e-6f, 1e-6f);
    }
    const TriangleInterpolation ti = interpolationOf(v);
    if (ti.degenerate) continue;
    for (int k = 0; k < 4; ++k) {
      const int rw = 1 + int(rng.uniform(0, 64)), rh = 1 + int(rng.uniform(0, 64));
      const int x0 = int(rng.uniform(0, float(w - rw))), y0 = int(rng.uniform(0, float(h - rh)));
      const PixelRect r{x0, y0, x0 + rw, y0 + rh};
      const bool below = allBelow(ti, ndc, r);
      if (FragmentStage::barycentricsBoundedOn(ti, ndc.map, r)) {
        INFO("triangle " << t << " rectangle " << r.x0 << "," << r.y0 << " " << rw << "x" << rh);
        REQUIRE(below);
        ++proven;
      } else {
        ++unproven;
        unprovenAndOver += !below;
      }
    }
  }
  INFO(proven << " proven, " << unproven << " not (" << unprovenAndOver << " of them with a centre over the bound)");
  CHECK(proven > 1000);  // it proves the usual case: not a check that always says no
  CHECK(unproven > 100);
}

TEST_CASE("barycentric bound: a rectangle that holds the triangle's horizon is not proven", "[interp]") {
  // The plane x − w/32 = 1 through the three vertices (clip x, y, w): the ray of NDC x_n = 1/32,
  // the centres of column 16 in a 32-pixel-wide viewport, never meets it, so s = Σk_i is 0 there
  // and B is unbounded (computed: huge, infinite or NaN).
  const Ndc ndc(32, 32);
  glm::dvec4 v[3] = {{1.0 + 2.0 / 32, -1.0, 0.0, 2.0}, {1.0 + 0.5 / 32, 0.5, 0.0, 0.5}, {1.0 + 1.0 / 32, 1.5, 0.0, 1.0}};
  const TriangleInterpolation ti = interpolationOf(v);
  REQUIRE(!ti.degenerate);
  REQUIRE(!(computedB(ti, ndc, 16, 5) < FragmentStage::kFlatBarycentricBound));
  CHECK(!FragmentStage::barycentricsBoundedOn(ti, ndc.map, PixelRect{10, 0, 20, 32}));
  CHECK(!FragmentStage::barycentricsBoundedOn(ti, ndc.map, PixelRect{16, 5, 17, 6}));
  // Away from it, B is moderate and proven: the check above is the horizon's, not a refusal of
  // every such triangle.
  CHECK(allBelow(ti, ndc, PixelRect{24, 0, 32, 32}));
  CHECK(FragmentStage::barycentricsBoundedOn(ti, ndc.map, PixelRect{24, 0, 32, 32}));
}

TEST_CASE("barycentric bound: the window depth's plane is within its margin of the long way at every pixel", "[interp]") {
  // FragmentStage::windowDepthPlane over a rectangle that barycentricsBoundedOn proved: at each
  // pixel centre the plane's value, ½·(a·x_n + (b·y_n + c)) + ½ as the span kernel takes it, is
  // within plane.error of interpolate()'s window z. The two differ by rounding only, a few units
  // of 2^−53 (so a margin of 0 fails); the margin must also be narrow enough to be of use.
  const int w = 256, h = 192;
  const Ndc ndc(w, h);
  test::BitStream rng(101);
  int planes = 0, pixels = 0, differing = 0;
  double widest = 0.0;
  for (int t = 0; t < 500; ++t) {
    glm::dvec4 v[3];
    for (auto& p : v) {
      const double cw = rng.uniform(0.1f, 4.0f);
      p = glm::dvec4(rng.uniform(-1.5f, 1.5f) * cw, rng.uniform(-1.5f, 1.5f) * cw, rng.uniform(-1.0f, 1.0f) * cw, cw);
    }
    if (t % 4 == 1) v[0].z = -v[0].w;                      // at the near plane
    if (t % 4 == 2) v[1].w = rng.uniform(-1.0f, 0.1f);     // a vertex behind the eye
    if (t % 4 == 3) v[2].z = v[2].w * 0.99999;             // near the far plane
    const TriangleInterpolation ti = interpolationOf(v);
    if (ti.degenerate) continue;
    for (int k = 0; k < 3; ++k) {
      const int rw = 1 + int(rng.uniform(0, 64)), rh = 1 + int(rng.uniform(0, 64));
      const int x0 = int(rng.uniform(0, float(w - rw))), y0 = int(rng.uniform(0, float(h - rh)));
      const PixelRect r{x0, y0, x0 + rw, y0 + rh};
      FragmentStage::RectangleBound bound;
      FragmentStage::WindowDepthPlane plane;
      if (!FragmentStage::barycentricsBoundedOn(ti, ndc.map, r, &bound) || !FragmentStage::windowDepthPlane(ti, bound, plane))
        continue;
      ++planes;
      widest = std::max(widest, plane.error);
      for (int y = r.y0; y < r.y1; ++y) {
        const double yn = double(y) * ndc.map[2] + ndc.map[3], rowPart = plane.b * yn + plane.c;
        for (int x = r.x0; x < r.x1; ++x) {
          const double xn = double(x) * ndc.map[0] + ndc.map[1];
          const double fromPlane = 0.5 * (plane.a * xn + rowPart) + 0.5, longWay = computedWindowZ(ti, ndc, x, y);
          INFO("triangle " << t << " pixel " << x << "," << y << " margin " << plane.error);
          REQUIRE(std::fabs(fromPlane - longWay) <= plane.error);
          ++pixels;
          differing += fromPlane != longWay;
        }
      }
    }
  }
  INFO(planes << " planes, " << pixels << " pixels, " << differing << " differing, widest margin " << widest);
  CHECK(planes > 500);
  CHECK(differing > 1000);     // the margin is needed
  CHECK(widest < 0x1p-32);     // and narrow: fp32 window depths near 1 are 2^−24 apart
}
