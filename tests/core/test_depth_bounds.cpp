// WindowDepthBounds (pipeline/depth_bounds.h), the interval behind the span's rejection of hidden
// runs, against the window z it must hold: the interpolation's expressions of
// pipeline/fragment_ops.h (k = M⁻¹·(x_n, y_n, 1), w = 1/Σk, b = k·w, z = ½·(Σ b_i z_i)/w + ½),
// evaluated here at every pixel of each run. Triangles are drawn from ordinary perspective views
// and from hostile ones (a vertex near or behind the eye plane, nearly edge-on, depths far
// outside [−w, w], magnitudes near fp32's ends): wherever the bound answers, every pixel's z lies
// inside it; for ordinary triangles it answers almost always and is tight.
#include <catch2/catch.hpp>

#include <cmath>

#include "pipeline/depth_bounds.h"
#include "support.h"

using namespace oitref;
using namespace oitref::detail;

namespace {

constexpr int kWidth = 320, kHeight = 200;

struct View {
  double sx, ox, sy, oy;  // x_n = x·sx + ox (FragmentStage's constructor)
};
View viewOf(int vx, int vy) {
  return {2.0 / kWidth, (0.5 - vx) * (2.0 / kWidth) - 1.0, 2.0 / kHeight, (0.5 - vy) * (2.0 / kHeight) - 1.0};
}

double windowZ(const TriangleInterpolation& t, double xn, double yn) {
  const auto& m = t.inverse;
  const double k0 = m[0][0] * xn + m[0][1] * yn + m[0][2];
  const double k1 = m[1][0] * xn + m[1][1] * yn + m[1][2];
  const double k2 = m[2][0] * xn + m[2][1] * yn + m[2][2];
  const double w = 1.0 / (k0 + k1 + k2);
  const double b0 = k0 * w, b1 = k1 * w, b2 = k2 * w;
  return 0.5 * ((b0 * t.clipZ[0] + b1 * t.clipZ[1] + b2 * t.clipZ[2]) / w) + 0.5;
}

// A clip-space vertex (fp32, as Geometry holds them) of kind `kind`.
glm::dvec4 vertex(test::BitStream& rng, int kind) {
  float w = rng.uniform(0.2f, 50.0f);
  if (kind == 1) w = std::ldexp(rng.uniform(0.5f, 1.0f), -int(rng.next() % 120));  // near the eye plane
  if (kind == 2) w = rng.uniform(-3.0f, 0.5f);                                        // either side of it
  if (kind == 3) w = std::ldexp(rng.uniform(0.5f, 1.0f), int(rng.next() % 250) - 125);
  const float x = rng.uniform(-1.5f, 1.5f) * w, y = rng.uniform(-1.5f, 1.5f) * w;
  float z = rng.uniform(-1.0f, 1.0f) * w;
  if (kind == 3) z = std::ldexp(rng.uniform(-1.0f, 1.0f), int(rng.next() % 250) - 125);
  return glm::dvec4(glm::vec4(x, y, z, w));
}

}  // namespace

TEST_CASE("depth bounds: every pixel's window z lies in the run's interval", "[depth]") {
  test::BitStream rng(91);
  int ordinaryRuns = 0, ordinaryBounded = 0, hostileBounded = 0, pixels = 0;
  double worstSlack = 0;  // (width of the interval − spread of the run's z), ordinary runs
  for (int trial = 0; trial < 6000; ++trial) {
    const int kind = trial % 5;  // 0 and 4 ordinary; 1–3 hostile
    glm::dvec4 v[3];
    for (glm::dvec4& p : v) p = vertex(rng, kind == 4 ? 0 : kind);
    if (kind == 4) v[2] = v[0] + (v[1] - v[0]) * double(rng.uniform(0.0f, 1.0f)) + glm::dvec4(1e-6, 0, 0, 0);  // edge-on
    const TriangleInterpolation t = interpolationOf(v);
    if (t.degenerate) continue;
    const View view = viewOf(int(rng.next() % 40) - 20, int(rng.next() % 40) - 20);
    WindowDepthBounds bounds;
    bounds.beginTriangle(t);
    for (int run = 0; run < 8; ++run) {
      const int y = int(rng.next() % kHeight);
      const int n = 1 + int(rng.next() % 64), x0 = int(rng.next() % (kWidth - n));
      const double yn = double(y) * view.sy + view.oy;
      bounds.beginRow(yn);
      double zLow, zHigh;
      const double first = double(x0) * view.sx + view.ox, last = double(x0 + n - 1) * view.sx + view.ox;
      const bool bounded = bounds.bound(first, last, zLow, zHigh);
      double lo = INFINITY, hi = -INFINITY;
      for (int x = x0; x < x0 + n; ++x) {
        const double z = windowZ(t, double(x) * view.sx + view.ox, yn);
        lo = std::min(lo, z), hi = std::max(hi, z);
        if (!bounded) continue;
        ++pixels;
        INFO("trial " << trial << " kind " << kind << " pixel " << x << "," << y << " z " << z << " in [" << zLow
                      << ", " << zHigh << "]");
        REQUIRE(z >= zLow);
        REQUIRE(z <= zHigh);
      }
      if (kind == 0) {
        ++ordinaryRuns;
        ordinaryBounded += bounded;
        if (bounded) worstSlack = std::max(worstSlack, (zHigh - zLow) - (hi - lo));
      } else {
        hostileBounded += bounded;
      }
    }
  }
  INFO(ordinaryBounded << " of " << ordinaryRuns << " ordinary runs bounded; worst slack " << worstSlack);
  CHECK(ordinaryBounded >= ordinaryRuns * 95 / 100);  // the bound is not refused where it should hold
  CHECK(worstSlack < 1e-9);                            // and is tight: far below a d24 step (6e-8)
  CHECK(hostileBounded > 1000);                        // the hostile kinds reach the checks too
  CHECK(pixels > 100000);
}
