// Ways of running a frame that exist for speed and must not change its bits:
//  * AttachmentPool: a frame whose attachments come from the pool, still holding another frame's
//    contents, has the bits of a frame rendered into fresh attachments, for every method (no
//    method reads an attachment before it clears or writes it);
//  * the span path (row spans, batched blending) against the per-fragment path, its oracle.
#include <catch2/catch.hpp>

#include <cstring>

#include "method_fixture.h"
#include "oitref/oit/method.h"
#include "tools/suite.h"

using namespace oitref;

TEST_CASE("methods: a pooled frame gives the bits of a fresh one", "[methods]") {
  const Scene scene = test::testScene();
  Scene other = scene;  // same size, different contents: what the pool holds before
  other.background = {0.9f, 0.1f, 0.6f};
  other.camera.position = {1.5f, -1.0f, 4.0f};
  const SceneGeometry geometry = buildSceneGeometry(scene), otherGeometry = buildSceneGeometry(other);
  Renderer renderer(RendererOptions{2, 16});
  int methods = 0;
  for (const MethodInfo& info : allMethods())
    for (const Profile& profile : {exactProfile(), llvmpipeProfile()}) {
      // The A-buffer keeps its lists here, so that they are compared too.
      auto method = info.name == "abuffer" ? makeMethod(info.name, {{"lists", "keep"}}) : makeMethod(info.name);
      const FrameResult fresh =
          method->render(FrameContext{scene, geometry, scene.width, scene.height, profile, renderer});
      AttachmentPool pool;
      pool.recycle(method->render(
          FrameContext{other, otherGeometry, other.width, other.height, profile, renderer, UINT64_MAX, &pool}));
      const size_t kept = pool.size();
      const FrameResult pooled =
          method->render(FrameContext{scene, geometry, scene.width, scene.height, profile, renderer, UINT64_MAX, &pool});
      INFO(info.name << " " << profile.describe());
      // The frame took its attachments from the pool (the ray cast has none: it does not
      // rasterize, and the pool keeps nothing it did not lend).
      if (info.name != "raycast") {
        CHECK(kept > 0);
        CHECK(pool.size() < kept);
      }
      CHECK(frameHash(pooled) == frameHash(fresh));
      // The A-buffer's fragment lists too, stored into the pool's kept buffer (the other scene's).
      const FragmentLists &pooledLists = pooled.fragmentLists, &freshLists = fresh.fragmentLists;
      CHECK(pooledLists.start == freshLists.start);
      REQUIRE(pooledLists.fragments.size() == freshLists.fragments.size());
      if (!freshLists.fragments.empty())  // memcmp's pointers must not be null, even for no bytes
        CHECK(std::memcmp(pooledLists.fragments.data(), freshLists.fragments.data(),
                          freshLists.fragments.size() * sizeof(TransparentFragment)) == 0);
      // Balanced: giving a frame back leaves the pool as it was, so repeated frames do not grow it.
      pool.recycle(FrameResult(pooled));
      CHECK(pool.size() == kept);
      methods += profile.describe() == exactProfile().describe();
    }
  CHECK(methods == int(allMethods().size()));
}

TEST_CASE("methods: the span path gives the per-fragment path's bits, every method and profile", "[methods]") {
  const Scene scene = test::testScene();
  const SceneGeometry geometry = buildSceneGeometry(scene);
  Renderer spans(RendererOptions{2, 16}), perFragment(RendererOptions{2, 16, true});
  int compared = 0;
  for (const MethodInfo& info : allMethods())
    for (const Profile& profile : {exactProfile(), llvmpipeProfile(), nvidiaProfile()}) {
      auto method = makeMethod(info.name);
      const FrameResult a = method->render(FrameContext{scene, geometry, scene.width, scene.height, profile, spans});
      const FrameResult b = method->render(FrameContext{scene, geometry, scene.width, scene.height, profile, perFragment});
      INFO(info.name << " " << profile.describe());
      CHECK(frameHash(a) == frameHash(b));
      CHECK(a.fragmentsShaded() == b.fragmentsShaded());
      ++compared;
    }
  CHECK(compared == 3 * int(allMethods().size()));
}
