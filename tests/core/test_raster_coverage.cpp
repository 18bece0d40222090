// Rasterization rules: every pixel of a shared-edge mesh exactly once, the top-left convention,
// and coverage of random on-grid triangles against an exact integer oracle written here.
#include <catch2/catch.hpp>

#include "render_helpers.h"
#include "support.h"

using namespace oitref;

namespace {

// A (cols+1)×(rows+1) vertex grid over [-5, w+5]×[-5, h+5] with jittered interior vertices
// (every third row and column left straight, giving exactly horizontal and vertical edges),
// each cell split along alternating diagonals.
Geometry jitteredGrid(int w, int h, int cols, int rows, int subpixelBits, uint32_t seed) {
  test::BitStream rng(seed);
  const double grid = 1.0 / (1 << subpixelBits);
  std::vector<glm::dvec2> v;
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= cols; ++i) {
      double x = -5 + (w + 10.0) * i / cols, y = -5 + (h + 10.0) * j / rows;
      if (i % 3 && j % 3 && i > 0 && j > 0 && i < cols && j < rows) {
        x += rng.uniform(-1.5f, 1.5f);
        y += rng.uniform(-1.5f, 1.5f);
      }
      if (j % 2) x = std::round(x);  // some vertices exactly on pixel boundaries...
      if (i % 4 == 1) y = std::round(y - 0.5) + 0.5;  // ...and some on pixel centres
      v.emplace_back(std::round(x / grid) * grid, std::round(y / grid) * grid);
    }
  std::vector<glm::dvec3> pts;
  auto at = [&](int i, int j) { return glm::dvec3(v[size_t(j * (cols + 1) + i)], 0.5); };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const glm::dvec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if ((i + j) % 2) pts.insert(pts.end(), {a, b, c, a, c, d});
      else pts.insert(pts.end(), {a, b, d, b, c, d});
      if (i == 2 && j == 1) std::swap(pts[pts.size() - 1], pts[pts.size() - 2]);  // one clockwise triangle
    }
  return test::windowTriangles(pts, w, h);
}

// Independent inside test on on-grid vertices, straight from the rule's definition: the sample
// is strictly inside every edge, or on an edge that is top or left (y up, counter-clockwise).
bool oracleInside(const glm::dvec2 v[3], double px, double py, int bits, FillConvention fill) {
  const double s = double(1 << bits);
  __int128 X[3], Y[3];
  for (int i = 0; i < 3; ++i) X[i] = (__int128)std::llround(v[i].x * s), Y[i] = (__int128)std::llround(v[i].y * s);
  __int128 area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
  if (area == 0) return false;
  int order[3] = {0, 1, 2};
  if (area < 0) std::swap(order[1], order[2]);
  const __int128 PX = (__int128)std::llround(px * s), PY = (__int128)std::llround(py * s);
  for (int e = 0; e < 3; ++e) {
    const int a = order[e], b = order[(e + 1) % 3];
    const __int128 cross = (X[b] - X[a]) * (PY - Y[a]) - (Y[b] - Y[a]) * (PX - X[a]);
    if (cross > 0) continue;
    if (cross < 0) return false;
    const bool left = Y[b] < Y[a];
    const bool horizontalTopOrBottom =
        Y[b] == Y[a] && (fill == FillConvention::TopLeft ? X[b] < X[a] : X[b] > X[a]);
    if (!(left || horizontalTopOrBottom)) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("raster: a shared-edge mesh covers every pixel exactly once", "[raster]") {
  Renderer r(RendererOptions{2, 16});
  for (int bits : {4, 8})
    for (FillConvention fill : {FillConvention::TopLeft, FillConvention::BottomLeft})
      for (uint32_t seed : {1u, 2u, 3u}) {
        const int w = 61, h = 47;
        RasterState rs;
        rs.subpixelBits = bits;
        rs.fill = fill;
        const auto count = test::coverageCount(r, jitteredGrid(w, h, 9, 7, bits, seed), w, h, rs);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            INFO("bits " << bits << " fill " << toString(fill) << " seed " << seed << " pixel " << x << "," << y);
            REQUIRE(count[size_t(y * w + x)] == 1.0f);
          }
      }
}

TEST_CASE("raster: a triangle fan around an inner vertex covers every pixel once", "[raster]") {
  Renderer r(RendererOptions{2, 8});
  const int w = 40, h = 30;
  std::vector<glm::dvec3> pts;
  const glm::dvec3 centre(17.5, 12.5, 0.5);  // exactly on a pixel centre
  const int n = 37;
  for (int i = 0; i < n; ++i) {
    const double a0 = 2 * M_PI * i / n, a1 = 2 * M_PI * (i + 1) / n;
    auto ring = [&](double a) { return glm::dvec3(std::round((centre.x + 80 * std::cos(a)) * 256) / 256,
                                                  std::round((centre.y + 80 * std::sin(a)) * 256) / 256, 0.5); };
    pts.insert(pts.end(), {centre, ring(a0), ring(a1)});
  }
  const auto count = test::coverageCount(r, test::windowTriangles(pts, w, h), w, h);
  for (float c : count) REQUIRE(c == 1.0f);
}

TEST_CASE("raster: top-left rule on a rectangle with edges through pixel centres", "[raster]") {
  Renderer r(RendererOptions{1, 8});
  const int w = 8, h = 8;
  // Rectangle (1.5,1.5)–(3.5,3.5): its edges pass exactly through pixel centres.
  const std::vector<glm::dvec3> quad = {{1.5, 1.5, .5}, {3.5, 1.5, .5}, {3.5, 3.5, .5},
                                        {1.5, 1.5, .5}, {3.5, 3.5, .5}, {1.5, 3.5, .5}};
  for (FillConvention fill : {FillConvention::TopLeft, FillConvention::BottomLeft}) {
    RasterState rs;
    rs.fill = fill;
    const auto count = test::coverageCount(r, test::windowTriangles(quad, w, h), w, h, rs);
    // Left edge x = 1.5 in, right edge x = 3.5 out. Top-left: top y = 3.5 in, bottom y = 1.5
    // out. Bottom-left: the reverse.
    const int yLo = fill == FillConvention::TopLeft ? 2 : 1;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool want = x >= 1 && x <= 2 && y >= yLo && y <= yLo + 1;
        INFO(toString(fill) << " pixel " << x << "," << y);
        REQUIRE(count[size_t(y * w + x)] == (want ? 1.0f : 0.0f));
      }
  }
}

TEST_CASE("raster: random on-grid triangles, slivers included, match the exact oracle", "[raster]") {
  Renderer r(RendererOptions{2, 16});
  const int w = 48, h = 40;
  test::BitStream rng(77);
  for (int bits : {4, 8})
    for (int trial = 0; trial < 300; ++trial) {
      const double g = 1.0 / (1 << bits);
      glm::dvec2 v[3];
      for (auto& p : v) p = {std::round(rng.uniform(-10, 58) / g) * g, std::round(rng.uniform(-10, 50) / g) * g};
      if (trial % 3 == 0) {  // sliver: one grid unit off the line through v0 and v1
        v[2] = v[0] + (v[1] - v[0]) * 0.5;
        v[2] = {std::floor(v[2].x / g) * g + g, std::floor(v[2].y / g) * g};
      }
      if (trial % 5 == 0) v[1].y = v[0].y;                                      // horizontal edge
      if (trial % 7 == 0) v[2].x = v[1].x;                                      // vertical edge
      if (trial % 11 == 0) v[0] = {std::floor(v[0].x) + 0.5, std::floor(v[0].y) + 0.5};  // vertex on a centre
      const FillConvention fill = trial % 2 ? FillConvention::TopLeft : FillConvention::BottomLeft;
      RasterState rs;
      rs.subpixelBits = bits;
      rs.fill = fill;
      const auto count = test::coverageCount(
          r, test::windowTriangles({{v[0], .5}, {v[1], .5}, {v[2], .5}}, w, h), w, h, rs);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const bool want = oracleInside(v, x + 0.5, y + 0.5, bits, fill);
          if ((count[size_t(y * w + x)] == 1.0f) != want)
            FAIL("bits " << bits << " trial " << trial << " pixel " << x << "," << y << " oracle " << want);
        }
    }
}

TEST_CASE("raster: culling and facing follow the window-space winding", "[raster]") {
  Renderer r(RendererOptions{1, 8});
  const int w = 8, h = 8;
  const std::vector<glm::dvec3> ccw = {{0, 0, .5}, {8, 0, .5}, {0, 8, .5}};
  const std::vector<glm::dvec3> cw = {{0, 0, .5}, {0, 8, .5}, {8, 0, .5}};
  auto covered = [&](const std::vector<glm::dvec3>& tri, CullMode cull, FrontFace ff) {
    RasterState rs;
    rs.cull = cull;
    rs.frontFace = ff;
    const auto c = test::coverageCount(r, test::windowTriangles(tri, w, h), w, h, rs);
    return c[0] == 1.0f;
  };
  CHECK(covered(ccw, CullMode::None, FrontFace::CounterClockwise));
  CHECK(covered(ccw, CullMode::Back, FrontFace::CounterClockwise));
  CHECK_FALSE(covered(ccw, CullMode::Front, FrontFace::CounterClockwise));
  CHECK_FALSE(covered(cw, CullMode::Back, FrontFace::CounterClockwise));
  CHECK(covered(cw, CullMode::Back, FrontFace::Clockwise));

  Image face(makeFormat(FormatId::R8), w, h);
  Framebuffer fb;
  fb.color[0] = &face;
  PipelineState st;
  const FragmentProgram prog{[](const FragmentInput& in, FragmentOutput& o) {
    o.write(0, glm::vec4(in.frontFacing ? 1.0f : 0.5f));
  }};
  r.draw(fb, st, test::windowTriangles(ccw, w, h), prog);
  CHECK(face.texel(0, 0)[0] == 255);
  r.draw(fb, st, test::windowTriangles(cw, w, h), prog);
  CHECK(face.texel(0, 0)[0] == 128);
}

TEST_CASE("raster: zero-area and non-finite triangles produce nothing, and are counted", "[raster]") {
  Renderer r(RendererOptions{1, 8});
  Image img(makeFormat(FormatId::R8), 8, 8);
  Framebuffer fb;
  fb.color[0] = &img;
  Geometry g = test::windowTriangles({{1, 1, .5}, {5, 5, .5}, {3, 3, .5}, {0, 0, .5}, {8, 0, .5}, {0, 8, .5}}, 8, 8);
  g.clipPositions[4].x = NAN;
  const DrawStats s = r.draw(fb, PipelineState{}, g, {[](const FragmentInput&, FragmentOutput& o) { o.write(0, glm::vec4(1)); }});
  CHECK(s.trianglesSubmitted == 2);
  CHECK(s.trianglesRasterized == 0);
  CHECK(s.trianglesNonFinite == 1);
  CHECK(s.fragmentsRasterized == 0);
}

TEST_CASE("raster: bad geometry and state are refused with a reason", "[raster]") {
  Renderer r(RendererOptions{1, 8});
  Image img(makeFormat(FormatId::R8), 8, 8);
  Framebuffer fb;
  fb.color[0] = &img;
  Geometry g = test::windowTriangles({{1, 1, .5}, {5, 5, .5}, {3, 1, .5}}, 8, 8);
  g.indices = {0, 1, 7};
  CHECK_THROWS_WITH(r.draw(fb, PipelineState{}, g, {}), Catch::Contains("index 2 is 7"));
  g.indices.clear();
  g.attributeCount = 2;
  CHECK_THROWS_WITH(r.draw(fb, PipelineState{}, g, {}), Catch::Contains("attribute floats"));
  g.attributeCount = 0;
  PipelineState st;
  st.raster.subpixelBits = 12;
  CHECK_THROWS_WITH(r.draw(fb, st, g, {}), Catch::Contains("subpixelBits"));
  st = PipelineState{};
  st.viewport = {4, 4, 8, 8};
  CHECK_THROWS_WITH(r.draw(fb, st, g, {}), Catch::Contains("viewport"));
  Image other(makeFormat(FormatId::R8), 4, 8);
  fb.color[1] = &other;
  CHECK_THROWS_WITH(r.draw(fb, PipelineState{}, g, {}), Catch::Contains("colour attachment 1"));
  CHECK_THROWS_AS(Renderer(RendererOptions{1, 48}), std::invalid_argument);
}
