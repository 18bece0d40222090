// Clipping: triangles crossing the near plane, reaching behind the camera, far outside the
// screen (guard band), checked against rays cast in double precision through each pixel.
// A pixel counts only where the ray and four rays 1/16 pixel around it agree; elsewhere the
// answer depends on sub-pixel snapping and either result is right.
#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include "render_helpers.h"
#include "support.h"

using namespace oitref;

namespace {

struct Camera {
  glm::dmat4 view, proj;
  double near, far;
  int w, h;
};

// Ray through window position (x, y) (pixels, y up) against the world-space triangle, counting a
// hit only between the near and far planes (view-space depth).
bool rayHits(const Camera& c, const glm::dvec3 tri[3], double x, double y) {
  const glm::dmat4 inv = glm::inverse(c.proj * c.view);
  const double xn = 2 * x / c.w - 1, yn = 2 * y / c.h - 1;
  glm::dvec4 a = inv * glm::dvec4(xn, yn, -1, 1), b = inv * glm::dvec4(xn, yn, 1, 1);
  const glm::dvec3 o = glm::dvec3(a) / a.w, d = glm::dvec3(b) / b.w - o;
  // Möller–Trumbore.
  const glm::dvec3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0], p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-300) return false;
  const glm::dvec3 s = o - tri[0];
  const double u = glm::dot(s, p) / det;
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(d, q) / det, t = glm::dot(e2, q) / det;
  if (u < 0 || v < 0 || u + v > 1) return false;
  const glm::dvec3 hit = o + t * d;
  const double viewZ = -(c.view * glm::dvec4(hit, 1)).z;
  return viewZ >= c.near && viewZ <= c.far;
}

void checkAgainstRays(const Camera& cam, const std::vector<glm::dvec3>& tris, int& certain) {
  Renderer r(RendererOptions{2, 16});
  const glm::dmat4 vp = cam.proj * cam.view;
  Geometry g;
  for (const auto& p : tris) g.clipPositions.push_back(glm::vec4(vp * glm::dvec4(p, 1)));
  const auto count = test::coverageCount(r, g, cam.w, cam.h);
  for (int y = 0; y < cam.h; ++y)
    for (int x = 0; x < cam.w; ++x) {
      int hits[5] = {0, 0, 0, 0, 0};
      const double off[5][2] = {{0, 0}, {1. / 16, 0}, {-1. / 16, 0}, {0, 1. / 16}, {0, -1. / 16}};
      for (int k = 0; k < 5; ++k)
        for (size_t t = 0; t + 2 < tris.size(); t += 3)
          hits[k] += rayHits(cam, &tris[t], x + 0.5 + off[k][0], y + 0.5 + off[k][1]);
      if (!std::all_of(hits, hits + 5, [&](int v) { return v == hits[0]; })) continue;
      ++certain;
      if (count[size_t(y * cam.w + x)] != float(hits[0]))
        FAIL("pixel " << x << "," << y << ": rasterized " << count[size_t(y * cam.w + x)] << ", rays " << hits[0]);
    }
}

Camera camera(int w, int h) {
  Camera c;
  c.w = w, c.h = h, c.near = 0.5, c.far = 20;
  c.view = glm::lookAt(glm::dvec3(0, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
  c.proj = glm::perspective(glm::radians(70.0), double(w) / h, c.near, c.far);
  return c;
}

}  // namespace

TEST_CASE("clipping: triangles crossing the near plane and behind the camera match ray casting", "[clip]") {
  const Camera cam = camera(64, 48);
  test::BitStream rng(31);
  int certain = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<glm::dvec3> tri;
    for (int k = 0; k < 3; ++k)  // depths from behind the camera (z > 0) to beyond the far plane
      tri.emplace_back(rng.uniform(-6, 6), rng.uniform(-5, 5), rng.uniform(-25, 4));
    if (trial % 4 == 0) tri[0].z = 2.0, tri[1].z = -3.0;  // one vertex behind the eye, one in front
    checkAgainstRays(cam, tri, certain);
  }
  CHECK(certain > 60 * 64 * 48 * 9 / 10);
}

TEST_CASE("clipping: a shared edge crossing the near plane stays watertight", "[clip]") {
  const Camera cam = camera(50, 40);
  Renderer r(RendererOptions{2, 16});
  const glm::dmat4 vp = cam.proj * cam.view;
  // A quad (two triangles) spanning from behind the camera to far away, larger than the view.
  const glm::dvec3 a(-30, -2, 3), b(30, -2, 3), c(30, 9, -18), d(-30, 9, -18);
  Geometry g;
  for (const auto& p : {a, b, c, a, c, d}) g.clipPositions.push_back(glm::vec4(vp * glm::dvec4(p, 1)));
  const auto count = test::coverageCount(r, g, cam.w, cam.h);
  int covered = 0;
  for (float v : count) {
    REQUIRE(v <= 1.0f);
    covered += v == 1.0f;
  }
  CHECK(covered > 100);
  int certain = 0;
  checkAgainstRays(cam, {a, b, c, a, c, d}, certain);
}

TEST_CASE("clipping: huge triangles far outside the screen cover it exactly once", "[clip]") {
  Renderer r(RendererOptions{2, 16});
  const int w = 33, h = 21;
  const double big = 1e7;  // window coordinates far beyond the guard band
  const std::vector<glm::dvec3> quad = {{-big, -big, .5}, {big, -big, .5}, {big, big, .5},
                                        {-big, -big, .5}, {big, big, .5}, {-big, big, .5}};
  for (float v : test::coverageCount(r, test::windowTriangles(quad, w, h), w, h)) REQUIRE(v == 1.0f);
}

TEST_CASE("clipping: depth clamp keeps geometry beyond the far plane", "[clip]") {
  Renderer r(RendererOptions{1, 8});
  const int w = 8, h = 8;
  // Window z 1.5: outside the depth range. Clipped away normally; kept (and clamped) with depth clamp.
  const auto far = test::windowTriangles({{0, 0, 1.5}, {16, 0, 1.5}, {0, 16, 1.5}}, w, h);
  CHECK(test::coverageCount(r, far, w, h)[0] == 0.0f);
  DepthState clamp;
  clamp.clamp = true;
  CHECK(test::coverageCount(r, far, w, h, {}, clamp)[0] == 1.0f);
}
