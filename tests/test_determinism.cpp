// Same inputs, same bits: the demo scene (clipping, depth, OVER on rgba8/rgba16f, MRT
// accumulation, a full-screen resolve) rendered with 1, 2, 3 and 8 threads and different tile
// sizes, in both profiles.
#include <catch2/catch.hpp>

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
    for (auto [threads, tile] : {std::pair{2, 64}, {3, 16}, {8, 8}, {8, 256}, {1, 32}}) {
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
