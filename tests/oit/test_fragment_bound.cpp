// The A-buffer's lower bound of the transparent fragments (methods/fragment_bound.h) against the
// fragments its counting pass actually counts: never above them, on every built-in scene at
// several sizes, and close to them where every transparent layer lies in front of the opaque
// geometry (dense: 300 screen-filling layers over a floor), which is what lets a frame that
// cannot fit be refused before anything is allocated.
#include <catch2/catch.hpp>

#include <filesystem>

#include "methods/fragment_bound.h"
#include "oitref/oit/method.h"

using namespace oitref;

namespace {

uint64_t countedFragments(const Scene& scene, const SceneGeometry& geometry, Renderer& renderer) {
  const FrameContext context{scene, geometry, scene.width, scene.height, exactProfile(), renderer};
  const FrameResult frame = makeMethod("abuffer")->render(context);
  REQUIRE(frame.stats.fragments.has_value());
  return *frame.stats.fragments;
}

}  // namespace

TEST_CASE("fragment bound: never above the A-buffer's count, and tight where nothing hides a layer", "[abuffer][bad_input]") {
  Renderer renderer(RendererOptions{2, 0});
  for (const auto& entry : std::filesystem::directory_iterator(OITREF_SOURCE_DIR "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    Scene scene = loadScene(entry.path().string());
    for (const auto& [w, h] : {std::pair{64, 36}, std::pair{320, 180}, std::pair{333, 97}}) {
      scene.width = w, scene.height = h;
      const SceneGeometry geometry = buildSceneGeometry(scene);
      const uint64_t bound = methods::transparentFragmentsAtLeast(geometry, w, h);
      const uint64_t counted = countedFragments(scene, geometry, renderer);
      INFO(entry.path().filename().string() << " at " << w << "x" << h << ": bound " << bound << ", counted " << counted);
      CHECK(bound <= counted);
      if (entry.path().stem() == "dense") CHECK(double(bound) >= 0.95 * double(counted));
    }
  }
}

TEST_CASE("fragment bound: a frame that cannot hold its fragments is refused before anything renders", "[abuffer][bad_input]") {
  Scene scene = loadScene(OITREF_SOURCE_DIR "/scenes/dense.json");
  const SceneGeometry geometry = buildSceneGeometry(scene);
  std::unique_ptr<Method> abuffer = makeMethod("abuffer", {{"lists", "keep"}});  // lists that must all fit
  // dense at 16384²: its 300 layers alone are about 80 billion fragments.
  CHECK_THROWS_WITH(checkMemory(*abuffer, 16384, 16384, geometry, uint64_t(12) << 30),
                    Catch::Contains("method 'abuffer' at 16384x16384 needs") && Catch::Contains("transparent fragments, at least"));
  uint64_t need = 0;
  for (const MemoryItem& i : abuffer->memoryNeed(320, 180, geometry)) need += i.bytes;
  CHECK_NOTHROW(checkMemory(*abuffer, 320, 180, geometry, need));
  CHECK_THROWS(checkMemory(*abuffer, 320, 180, geometry, need - 1));
}
