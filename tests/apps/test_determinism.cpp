// Same inputs, same bits: the demo scene (clipping, depth, OVER on rgba8/rgba16f, MRT
// accumulation, a full-screen resolve) rendered with 1, 2, 3 and 8 threads and different tile
// sizes, in both profiles.
#include <catch2/catch.hpp>

#include <cfenv>

#if defined(__x86_64__)
#include <xmmintrin.h>
#endif

#include "oitref/core/blend.h"
#include "oitref/core/renderer.h"
#include "tools/demo_scene.h"

using namespace oitref;

TEST_CASE("determinism: bit-identical output for any thread count and tile size", "[determinism]") {
  for (const char* profile : {"exact", "llvmpipe"}) {
    tools::DemoOptions o;
    o.width = 173;
    o.height = 97;
    o.triangles = 300;
    o.profile = parseProfile(profile);
    Renderer reference(RendererOptions{1, 64});
    const tools::DemoResult want = tools::renderDemo(reference, o);
    // Tile 0 is automatic (Renderer::tileShapeFor): 128×32 with one thread here, 64×16 with more.
    for (auto [threads, tile] : {std::pair{2, 64}, {3, 16}, {8, 8}, {8, 256}, {1, 32}, {1, 0}, {2, 0}, {7, 0}}) {
      Renderer r(RendererOptions{threads, tile});
      const tools::DemoResult got = tools::renderDemo(r, o);
      REQUIRE(got.images.size() == want.images.size());
      for (size_t i = 0; i < want.images.size(); ++i) {
        INFO(profile << " " << want.images[i].name << " threads " << threads << " tile " << tile);
        CHECK(got.images[i].image.sameBits(want.images[i].image));
      }
      for (size_t i = 0; i < want.passes.size(); ++i)
        CHECK(got.passes[i].second.fragmentsWritten == want.passes[i].second.fragmentsWritten);
    }
  }
}

TEST_CASE("determinism: the two profiles differ where they should", "[determinism]") {
  tools::DemoOptions o;
  o.width = 64;
  o.height = 48;
  Renderer r(RendererOptions{2, 64});
  const auto exact = tools::renderDemo(r, o);
  o.profile = llvmpipeProfile();
  const auto llvm = tools::renderDemo(r, o);
  CHECK_FALSE(exact.images[0].image.sameBits(llvm.images[0].image));  // rgba8 OVER: integer blending
  CHECK_FALSE(exact.images[1].image.sameBits(llvm.images[1].image));  // rgba16f: round toward zero
}

TEST_CASE("determinism: the caller's floating-point environment does not change the bits", "[determinism]") {
  // Perspective triangles with interpolated colours, blended OVER into rgba16f and rgba8, plus a
  // full-screen pass doing arithmetic: rendered normally, then again from a thread whose
  // environment rounds toward zero and (on x86) flushes denormals — as a host application might.
  const int w = 96, h = 64;
  Geometry g = Geometry::fromVertexShader(300, 4, [](size_t v, float* a) {
    const float t = float(v) * 0.7f;
    for (int k = 0; k < 4; ++k) a[k] = 0.5f + 0.45f * std::sin(t * float(k + 1));
    const float z = 0.5f + 0.4f * std::cos(t * 0.37f), ww = 0.3f + 3.0f * float(v % 7);
    return glm::vec4(std::sin(t) * ww, std::cos(t * 1.3f) * ww, (2 * z - 1) * ww, ww);
  });
  auto render = [&](Renderer& r) {
    std::vector<Image> out;
    for (const char* f : {"rgba16f", "rgba8"}) {
      Image img(parseFormat(f), w, h);
      img.clear({0.1f, 0.2f, 0.3f, 1}, exactProfile());
      Framebuffer fb;
      fb.color[0] = &img;
      PipelineState st;
      st.blend[0] = BlendState::same(BlendEquation::Add, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha);
      r.draw(fb, st, g, {[](const FragmentInput& in, FragmentOutput& o) { o.write(0, in.vec4At(0) * 1.1f); }});
      r.drawFullscreen(fb, st, {[](const FragmentInput& in, FragmentOutput& o) {
                         o.write(0, glm::vec4(in.fragCoord.x / 7.0f, in.fragCoord.y / 3.0f, 0.3f, 0.1f));
                       }});
      out.push_back(std::move(img));
    }
    return out;
  };
  Renderer r(RendererOptions{2, 16});
  const auto want = render(r);
  const int savedRounding = std::fegetround();
  std::fesetround(FE_TOWARDZERO);
#if defined(__x86_64__)
  const unsigned savedCsr = _mm_getcsr();
  _mm_setcsr(savedCsr | 0x8040);  // FTZ | DAZ
#endif
  std::vector<Image> got;
  {
    Renderer hostile(RendererOptions{2, 16});
    got = render(hostile);
  }
  // The per-texel entry points shaders call from the caller's thread: a value that rounds, and
  // one whose fp16 is denormal (FTZ would flush it).
  Image stored(parseFormat("rgba16f"), 2, 1);
  stored.store(0, 0, glm::vec4(1.0f / 3.0f, 0x1p-20f, -0x1.8p-23f, 0.7f), exactProfile());
  blendIntoTexel(stored.format(), BlendState::same(BlendEquation::Add, BlendFactor::SrcAlpha, BlendFactor::One),
                 glm::vec4(0.0f), exactProfile(), glm::vec4(0x1p-21f, 1.0f / 7.0f, 2.0f / 3.0f, 0.3f), stored.texel(1, 0));
  // The guard restores the caller's environment.
  CHECK(std::fegetround() == FE_TOWARDZERO);
#if defined(__x86_64__)
  CHECK((_mm_getcsr() & 0x8040u) == 0x8040u);
  _mm_setcsr(savedCsr);
#endif
  std::fesetround(savedRounding);
  CHECK(got[0].sameBits(want[0]));
  CHECK(got[1].sameBits(want[1]));
  Image expected(parseFormat("rgba16f"), 2, 1);
  expected.store(0, 0, glm::vec4(1.0f / 3.0f, 0x1p-20f, -0x1.8p-23f, 0.7f), exactProfile());
  blendIntoTexel(expected.format(), BlendState::same(BlendEquation::Add, BlendFactor::SrcAlpha, BlendFactor::One),
                 glm::vec4(0.0f), exactProfile(), glm::vec4(0x1p-21f, 1.0f / 7.0f, 2.0f / 3.0f, 0.3f), expected.texel(1, 0));
  CHECK(stored.sameBits(expected));
}
