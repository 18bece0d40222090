// Attribute and depth interpolation against long-double closed forms.
//  * Unclipped triangles: window positions from the fp32 clip coordinates, λ_i by areas, depth
//    Σλ_i z_i, perspective-correct b_i = (λ_i/w_i)/Σ(λ_j/w_j) (GL 4.6 eq. 14.9, 14.10) — a
//    different route from the pipeline's homogeneous one. Within 1 ulp.
//  * Clipped triangles: homogeneous barycentrics of the original triangle solved from its clip
//    coordinates with glm's inverse. Interpolation ignores snapping and clipping (they decide
//    coverage only), so the results must be within 1 ulp (1e-7 absolute near zero) plus the
//    error of solving a 3×3 system in double, 64·cond(M)·2^-53 (large when a vertex is near
//    the eye plane).
//  * A program that reads fewer attributes (FragmentProgram::attributesRead) gets the same bits.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "render_helpers.h"
#include "support.h"

using namespace oitref;
using ld = long double;

namespace {

struct Captured {
  Image attr, misc;  // attr: rgba32f attributes; misc: (depth, viewDepth, primitiveId, 1)
};

Captured capture(Renderer& r, const Geometry& g, int w, int h) {
  Captured c{Image(makeFormat(FormatId::RGBA32F), w, h), Image(makeFormat(FormatId::RGBA32F), w, h)};
  c.attr.clear(glm::vec4(NAN), exactProfile());
  c.misc.clear(glm::vec4(NAN), exactProfile());
  Framebuffer fb;
  fb.color[0] = &c.attr;
  fb.color[1] = &c.misc;
  r.draw(fb, PipelineState{}, g, {[](const FragmentInput& in, FragmentOutput& o) {
           o.write(0, in.vec4At(0));
           o.write(1, {in.depth, in.viewDepth, float(in.primitiveId), 1.0f});
         }});
  return c;
}

double ulpsApart(float got, ld want) {
  const float wf = float(want);
  const double ulp = std::max(double(std::nextafter(std::fabs(wf), INFINITY) - std::fabs(wf)), 1e-30);
  return double(std::fabs(ld(got) - want) / ulp);
}

// The flat-attribute tests' triangles: kind 0 ordinary, 1 a sliver, 2 with a vertex behind the
// eye (clipped), 3 nearly edge-on (the plane of clip x, y, w nearly through the eye).
void flatTestTriangle(test::BitStream& rng, int kind, glm::vec4 v[3]) {
  for (int i = 0; i < 3; ++i)
    v[i] = glm::vec4(rng.uniform(-1.5f, 1.5f), rng.uniform(-1.5f, 1.5f), rng.uniform(-0.9f, 0.9f), rng.uniform(0.5f, 2.0f));
  if (kind == 1) v[2] = v[0] + (v[1] - v[0]) * 0.5f + glm::vec4(rng.uniform(-1e-4f, 1e-4f), rng.uniform(-1e-4f, 1e-4f), 0, 0);
  if (kind == 2) v[1].w = rng.uniform(-1.0f, 0.05f), v[1].z = -v[1].w * 0.5f;
  if (kind == 3) {
    const float a = rng.uniform(0.2f, 0.8f);
    v[2] = v[0] * a + v[1] * (1.0f - a);
    v[2].x += rng.uniform(-1e-5f, 1e-5f);
    v[2].w *= 1.0f + rng.uniform(-1e-5f, 1e-5f);
  }
}
// Values next to powers of two, subnormal, the largest float and negative ones.
constexpr float kFlatSpecials[] = {1.0f, 0x1.fffffep0f, 0x1p-130f, -3.0e38f, 0.1f, -7.5f, 0x1p-149f, 0.999999940f};

}  // namespace

TEST_CASE("interpolation: perspective-correct attributes and window-linear depth, unclipped", "[interp]") {
  Renderer r(RendererOptions{2, 16});
  const int w = 64, h = 48;
  test::BitStream rng(17);
  double worst = 0, worstDepth = 0;
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Geometry g;
    g.attributeCount = 4;
    ld X[3], Y[3], Z[3], W[3], A[3][4];
    for (int k = 0; k < 3; ++k) {
      // Window position on the 1/256 grid, depth in (0,1), w in [0.2, 50]: strong perspective.
      const double x = std::round(rng.uniform(-8, 72) * 256) / 256, y = std::round(rng.uniform(-8, 56) * 256) / 256;
      const float z = rng.uniform(0.05f, 0.95f), ww = rng.uniform(0.2f, 50.0f);
      const glm::vec4 ndc = test::windowToClip(x, y, z, w, h);
      g.clipPositions.push_back(glm::vec4(ndc.x * ww, ndc.y * ww, ndc.z * ww, ww));
      // The triangle is what its fp32 clip coordinates say, a few 1e-7 off the grid values.
      const glm::vec4& c = g.clipPositions.back();
      X[k] = (ld(c.x) / ld(c.w) * 0.5L + 0.5L) * w, Y[k] = (ld(c.y) / ld(c.w) * 0.5L + 0.5L) * h, W[k] = ww;
      (void)x, (void)y;
      // The pipeline computes window z from the fp32 clip coordinates: so does the oracle.
      Z[k] = 0.5L * (ld(g.clipPositions.back().z) / ld(ww)) + 0.5L;
      for (int a = 0; a < 4; ++a) {
        A[k][a] = rng.uniform(-100, 100);
        g.attributes.push_back(float(A[k][a]));
      }
    }
    const Captured c = capture(r, g, w, h);
    const ld area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        const glm::vec4 got = c.attr.fetch(px, py);
        if (std::isnan(got.x)) continue;
        const ld sx = px + 0.5L, sy = py + 0.5L;
        ld l[3];
        for (int i = 0; i < 3; ++i) {
          const int a = (i + 1) % 3, b = (i + 2) % 3;
          l[i] = ((X[b] - X[a]) * (sy - Y[a]) - (Y[b] - Y[a]) * (sx - X[a])) / area;
        }
        ld sum = 0;
        for (int i = 0; i < 3; ++i) sum += l[i] / W[i];
        for (int a = 0; a < 4; ++a) {
          ld v = 0;
          for (int i = 0; i < 3; ++i) v += (l[i] / W[i]) / sum * A[i][a];
          worst = std::max(worst, ulpsApart(got[a], v) * (std::fabs(v) > 1e-3L ? 1.0 : 0.0));
          REQUIRE(std::fabs(ld(got[a]) - v) <= 1e-5L * 100);  // absolute sanity bound
        }
        const ld depth = l[0] * Z[0] + l[1] * Z[1] + l[2] * Z[2];
        const glm::vec4 misc = c.misc.fetch(px, py);
        worstDepth = std::max(worstDepth, ulpsApart(misc.x, depth));
        REQUIRE(ulpsApart(misc.y, 1 / sum) <= 1.0);  // view depth = interpolated w
        ++checked;
      }
  }
  INFO("worst attribute error " << worst << " ulps, depth " << worstDepth << " ulps over " << checked << " fragments");
  CHECK(checked > 5000);
  CHECK(worst <= 1.0);
  CHECK(worstDepth <= 1.0);
}

TEST_CASE("interpolation: clipped triangles interpolate as the original triangle", "[interp]") {
  Renderer r(RendererOptions{2, 16});
  const int w = 48, h = 40;
  const glm::dmat4 proj = glm::perspective(glm::radians(75.0), double(w) / h, 0.3, 30.0);
  test::BitStream rng(23);
  double worst = 0;
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Geometry g;
    g.attributeCount = 4;
    glm::dvec4 clip[3];
    ld A[3][4];
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 p(rng.uniform(-5, 5), rng.uniform(-5, 5), k == 0 ? rng.uniform(-0.2f, 1.0f) : rng.uniform(-15, -1));
      g.clipPositions.push_back(glm::vec4(proj * glm::dvec4(p, 1)));
      clip[k] = glm::dvec4(g.clipPositions.back());  // exactly the fp32 values the pipeline sees
      for (int a = 0; a < 4; ++a) {
        A[k][a] = rng.uniform(-1, 1);
        g.attributes.push_back(float(A[k][a]));
      }
    }
    const Captured c = capture(r, g, w, h);
    // Homogeneous barycentrics: Σ b_i (x_i, y_i, w_i) ∝ (x_ndc, y_ndc, 1), solved in long double
    // by Cramer's rule.
    const ld m[3][3] = {{ld(clip[0].x), ld(clip[1].x), ld(clip[2].x)},
                        {ld(clip[0].y), ld(clip[1].y), ld(clip[2].y)},
                        {ld(clip[0].w), ld(clip[1].w), ld(clip[2].w)}};
    auto det3 = [](const ld a[3][3]) {
      return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    const ld det = det3(m);
    // The pipeline solves in double: its error is about cond(M)·2^-53 (∞-norm condition number).
    ld norm = 0, normInv = 0;
    for (int r = 0; r < 3; ++r) norm = std::max(norm, std::fabs(m[r][0]) + std::fabs(m[r][1]) + std::fabs(m[r][2]));
    for (int r = 0; r < 3; ++r) {
      ld row = 0;
      for (int c = 0; c < 3; ++c) {
        const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
        row += std::fabs((m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det);
      }
      normInv = std::max(normInv, row);
    }
    const ld conditionTerm = 64 * norm * normInv * std::ldexp(1.0L, -53);
    auto closedForm = [&](double sx, double sy, int a) {
      const ld rhs[3] = {ld(2 * sx / w - 1), ld(2 * sy / h - 1), 1};
      ld b[3];
      for (int i = 0; i < 3; ++i) {
        ld mi[3][3];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) mi[r][c] = c == i ? rhs[r] : m[r][c];
        b[i] = det3(mi) / det;
      }
      const ld sum = b[0] + b[1] + b[2];
      return (b[0] * A[0][a] + b[1] * A[1][a] + b[2] * A[2][a]) / sum;
    };
    const double delta = 0.5 * std::sqrt(2.0) / 256.0, step = 1.0 / 16;
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        const glm::vec4 got = c.attr.fetch(px, py);
        if (std::isnan(got.x)) continue;
        const double sx = px + 0.5, sy = py + 0.5;
        for (int a = 0; a < 4; ++a) {
          const ld v = closedForm(sx, sy, a);
          ld gradient = 0;
          for (auto [dx, dy] : {std::pair{step, 0.0}, {-step, 0.0}, {0.0, step}, {0.0, -step}})
            gradient = std::max(gradient, std::fabs(closedForm(sx + dx, sy + dy, a) - v) / ld(step));
          (void)gradient, (void)delta;
          // M⁻¹ from glm in double against the pipeline's adjugate: a few double roundings,
          // then one fp32 rounding; attributes near zero are judged in absolute terms.
          const ld ulp = ld(std::nextafter(std::fabs(float(v)), INFINITY) - std::fabs(float(v)));
          const ld bound = std::max(ulp, ld(1e-7f)) + conditionTerm;
          const ld err = std::fabs(ld(got[a]) - v);
          worst = std::max(worst, double(err / bound));
          if (err > bound) FAIL("trial " << trial << " pixel " << px << "," << py << " attribute " << a << ": got " << got[a]
                                         << ", closed form " << double(v) << ", bound " << double(bound));
        }
        ++checked;
      }
  }
  INFO("worst error " << worst << " ulps over " << checked << " fragments");
  CHECK(checked > 3000);
}

TEST_CASE("interpolation: a program that reads fewer attributes gets those, bit for bit", "[interp]") {
  // FragmentProgram::attributesRead: only the leading attributes are interpolated, with the same
  // bits as when all are; the shader sees the count. Spans and one fragment at a time.
  const int w = 40, h = 32;
  test::BitStream rng(31);
  for (bool perFragment : {false, true}) {
    Renderer r(RendererOptions{2, 16, perFragment});
    Geometry g;
    g.attributeCount = 6;
    for (int k = 0; k < 9; ++k) {
      g.clipPositions.push_back(glm::vec4(rng.uniform(-1.5f, 1.5f), rng.uniform(-1.5f, 1.5f), rng.uniform(-0.9f, 0.9f), rng.uniform(0.5f, 2.0f)));
      for (int a = 0; a < 6; ++a) g.attributes.push_back(rng.uniform(-3, 3));
    }
    for (uint32_t i = 0; i < 9; ++i) g.indices.push_back(i);
    auto render = [&](int read) {
      Image out(makeFormat(FormatId::RGBA32F), w, h);
      out.clear(glm::vec4(NAN), exactProfile());
      Framebuffer fb;
      fb.color[0] = &out;
      FragmentProgram program = programOf([read](const FragmentInput& in, FragmentOutput& o) {
        if (in.attributeCount != (read < 0 ? 6 : read)) return o.write(0, glm::vec4(-1.0f));
        o.write(0, in.vec4At(0));
      });
      program.attributesRead = read;
      r.draw(fb, PipelineState{}, g, program);
      return out;
    };
    const Image all = render(-1), four = render(4);
    int covered = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::vec4 a = all.fetch(x, y), b = four.fetch(x, y);
        INFO("pixel " << x << "," << y << (perFragment ? " per fragment" : " spans"));
        REQUIRE(std::memcmp(&a, &b, sizeof a) == 0);
        covered += !std::isnan(a.x);
      }
    CHECK(covered > 100);
  }
}

TEST_CASE("interpolation: an attribute equal at the three vertices gives its value, as the per-fragment path", "[interp]") {
  // The span path takes an attribute whose vertices agree (finite, not zero) as that value where
  // the batch's barycentrics are bounded (FragmentStage::flatAttributeValue). The oracle is the
  // per-fragment path, which always computes Σ b_i·a_i: the bytes must be equal, on ordinary
  // triangles, slivers, triangles clipped at the eye plane and nearly edge-on ones (their B is
  // proven bounded per triangle and tile too, as for a triangle whose attributes are all flat), for values next to powers of two,
  // subnormal, the largest float and negative ones; and a flat attribute must come out as its
  // vertices' value (the proof's claim), checked where the pixel is covered.
  const int w = 48, h = 40;
  test::BitStream rng(53);
  Geometry g;
  g.attributeCount = 4;
  int triangles = 0;
  for (int t = 0; t < 120; ++t) {
    glm::vec4 v[3];
    flatTestTriangle(rng, t % 4, v);
    const float flat = t % 2 ? kFlatSpecials[size_t(t / 2) % 8] : rng.uniform(-4, 4);
    const float shared = rng.uniform(-3, 3);
    for (int i = 0; i < 3; ++i) {
      g.clipPositions.push_back(v[i]);
      // Attributes 0 and 2 flat, 1 varying (in every fifth triangle equal at two vertices only),
      // 3 flat but zero, +0 or −0 (left to the general path, whose lanes must keep −0 as the
      // scalar does; 2 is −0 too where a is the smallest subnormal).
      const float varying = t % 5 == 0 && i < 2 ? shared : rng.uniform(-3, 3);
      g.attributes.insert(g.attributes.end(), {flat, varying, -flat * 0.5f, t % 4 ? 0.0f : -0.0f});
      g.indices.push_back(uint32_t(g.clipPositions.size() - 1));
    }
    ++triangles;
  }
  Image out[2] = {Image(makeFormat(FormatId::RGBA32F), w, h), Image(makeFormat(FormatId::RGBA32F), w, h)};
  for (int perFragment = 0; perFragment < 2; ++perFragment) {
    Renderer r(RendererOptions{2, 16, perFragment == 1});
    out[perFragment].clear(glm::vec4(NAN), exactProfile());
    Framebuffer fb;
    fb.color[0] = &out[perFragment];
    // programOf: with a batch shader, which takes the span path's batched interpolation.
    r.draw(fb, PipelineState{}, g, programOf([](const FragmentInput& in, FragmentOutput& o) { o.write(0, in.vec4At(0)); }));
  }
  REQUIRE(out[0].bytes() == out[1].bytes());
  // Each pixel holds the last triangle's fragment that covered it: its flat values are a and −a/2.
  int covered = 0, matched = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec4 a = out[0].fetch(x, y);
      if (std::isnan(a.x)) continue;
      ++covered;
      matched += a.z == -a.x * 0.5f && a.w == 0.0f;  // ±0
    }
  INFO(triangles << " triangles");
  CHECK(covered > 500);
  CHECK(matched == covered);
}

TEST_CASE("interpolation: a triangle whose attributes are all flat, drawn without interpolating them, as the per-fragment path", "[interp]") {
  // A program that reads no depth (FragmentProgram::readsDepth) and a triangle whose attributes
  // are all equal at its vertices: where FragmentStage::barycentricsBoundedOn proves B bounded
  // over the triangle's pixels in a tile, its runs reach the shader with the vertices' values,
  // not interpolated at all. The oracle is the per-fragment path, which interpolates each one.
  // Triangles: ordinary ones, slivers, ones clipped at the eye plane and ones nearly edge-on.
  const int w = 56, h = 44;
  test::BitStream rng(71);
  Geometry g;
  g.attributeCount = 3;
  for (int t = 0; t < 120; ++t) {
    glm::vec4 v[3];
    flatTestTriangle(rng, t % 4, v);
    const float a0 = t % 2 ? kFlatSpecials[size_t(t / 2) % 8] : rng.uniform(-4, 4), a1 = rng.uniform(0.5f, 3.0f);
    for (int i = 0; i < 3; ++i) {
      g.clipPositions.push_back(v[i]);
      g.attributes.insert(g.attributes.end(), {a0, a1, -a0 * 0.5f});
      g.indices.push_back(uint32_t(g.clipPositions.size() - 1));
    }
  }
  Image out[2] = {Image(makeFormat(FormatId::RGBA32F), w, h), Image(makeFormat(FormatId::RGBA32F), w, h)};
  for (int perFragment = 0; perFragment < 2; ++perFragment) {
    Renderer r(RendererOptions{2, 16, perFragment == 1});
    out[perFragment].clear(glm::vec4(NAN), exactProfile());
    Framebuffer fb;
    fb.color[0] = &out[perFragment];
    FragmentProgram program = programOf([](const FragmentInput& in, FragmentOutput& o) {
      o.write(0, glm::vec4(in.attribute(0), in.attribute(1), in.attribute(2), float(in.primitiveId)));
    });
    program.readsDepth = false;
    r.draw(fb, PipelineState{}, g, program);
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec4 a = out[0].fetch(x, y), b = out[1].fetch(x, y);
      INFO("pixel " << x << "," << y << ": " << a.x << " " << a.y << " " << a.z << " " << a.w << " per fragment " << b.x
                    << " " << b.y << " " << b.z << " " << b.w);
      REQUIRE(std::memcmp(&a, &b, sizeof a) == 0);
    }
  int covered = 0, matched = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec4 a = out[0].fetch(x, y);
      if (std::isnan(a.x)) continue;
      ++covered;
      matched += a.z == -a.x * 0.5f;
    }
  CHECK(covered > 1000);
  CHECK(matched == covered);
}

TEST_CASE("interpolation: a flat triangle's window depth from its plane is interpolate()'s, as the per-fragment path", "[interp]") {
  // A program that reads the window depth but not the view depth (FragmentProgram::readsViewDepth)
  // drawing triangles whose attributes are all flat: where the pipeline proves the depth test
  // passes (or there is none), positionSpan takes gl_FragCoord.z from the triangle's depth plane
  // where it proves the fp32 the same (FragmentStage::windowDepthsFromPlane). The oracle is the
  // per-fragment path, which interpolates each fragment's depth the long way. Triangles spanning
  // a wide range of depths (a vertex near the near plane), slivers, clipped ones; with no depth
  // buffer, and against one cleared to 1 with LESS and no writes (every run provably passes).
  const int w = 64, h = 48;
  test::BitStream rng(83);
  Geometry g;
  g.attributeCount = 2;
  for (int t = 0; t < 150; ++t) {
    glm::vec4 v[3];
    for (auto& p : v) {
      const float cw = rng.uniform(0.3f, 3.0f);
      p = glm::vec4(rng.uniform(-1.5f, 1.5f) * cw, rng.uniform(-1.5f, 1.5f) * cw, rng.uniform(-0.99f, 0.99f) * cw, cw);
    }
    if (t % 5 == 1) v[0].z = -v[0].w * 0.999999f;  // at the near plane
    if (t % 5 == 2) v[2] = v[0] + (v[1] - v[0]) * 0.5f + glm::vec4(rng.uniform(-1e-4f, 1e-4f), rng.uniform(-1e-4f, 1e-4f), 0, 0);
    if (t % 5 == 3) v[1].w = rng.uniform(-1.0f, 0.05f), v[1].z = -v[1].w * 0.5f;  // clipped at the eye plane
    const float a0 = rng.uniform(-4, 4), a1 = rng.uniform(0.5f, 3.0f);
    for (int i = 0; i < 3; ++i) {
      g.clipPositions.push_back(v[i]);
      g.attributes.insert(g.attributes.end(), {a0, a1});
      g.indices.push_back(uint32_t(g.clipPositions.size() - 1));
    }
  }
  for (int tested = 0; tested < 2; ++tested) {
    Image out[2] = {Image(makeFormat(FormatId::RGBA32F), w, h), Image(makeFormat(FormatId::RGBA32F), w, h)};
    for (int perFragment = 0; perFragment < 2; ++perFragment) {
      Renderer r(RendererOptions{2, 16, perFragment == 1});
      out[perFragment].clear(glm::vec4(NAN), exactProfile());
      DepthBuffer depth(DepthFormat::D32F, w, h);
      Framebuffer fb;
      fb.color[0] = &out[perFragment];
      PipelineState state;
      if (tested) {
        fb.depth = &depth;
        state.depth.testEnabled = true;
        state.depth.func = CompareFunc::Less;
        state.depth.writeMask = false;
      }
      FragmentProgram program = programOf([](const FragmentInput& in, FragmentOutput& o) {
        o.write(0, glm::vec4(in.depth, in.attribute(0), in.attribute(1), float(in.primitiveId)));
      });
      program.readsViewDepth = false;
      r.draw(fb, state, g, program);
    }
    int covered = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::vec4 a = out[0].fetch(x, y), b = out[1].fetch(x, y);
        INFO((tested ? "depth-tested" : "no depth test") << " pixel " << x << "," << y << ": " << a.x << " " << a.w
                                                           << " per fragment " << b.x << " " << b.w);
        REQUIRE(std::memcmp(&a, &b, sizeof a) == 0);
        covered += !std::isnan(a.y);
      }
    CHECK(covered > 1500);
  }
}
