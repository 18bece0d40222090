// The two ground truths, which share no visibility code: the rasterized A-buffer and Embree ray
// casting, on every built-in scene. At least 99.9 % of the pixels agree within 1e-5; every other
// pixel lies on an object's edge (the set of objects covering it differs from a neighbour's),
// where sub-pixel snapping and ray-triangle tests may rightly disagree. An alpha-tested object's
// discarded texels are no cover, so the edges of its mask count as edges too.
#include <catch2/catch.hpp>

#include <set>

#include "oitref/oit/frame.h"
#include "oitref/oit/method.h"
#include "tools/suite.h"

using namespace oitref;

TEST_CASE("ground truth: the A-buffer and the ray caster agree on every built-in scene", "[groundtruth]") {
  Renderer renderer(RendererOptions{2, 64});
  for (const std::string& path : tools::sceneFiles(OITREF_SOURCE_DIR "/scenes")) {
    const SceneFrames frames(loadScene(path), renderer);
    const Scene& scene = frames.scene();
    const FrameResult abuffer = frames.render(*makeMethod("abuffer", {{"lists", "keep"}}));
    const FrameResult raycast = frames.render(*makeMethod("raycast"));
    const int w = scene.width, h = scene.height;
    // The opaque objects' cover, one object at a time over a background no surface can have.
    std::vector<std::pair<uint32_t, Image>> opaqueCover;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      if (scene.objects[i].isTransparent()) continue;
      Scene alone = scene;
      alone.objects = {scene.objects[i]};
      alone.background = glm::vec3(-1.0f);
      const SceneGeometry g = buildSceneGeometry(alone);
      opaqueCover.emplace_back(uint32_t(i), makeMethod("opaque")->render(FrameContext{alone, g, w, h, exactProfile(), renderer}).finalFloat);
    }
    auto objectsAt = [&](int x, int y) {
      std::set<uint32_t> objects;
      for (const TransparentFragment& f : abuffer.fragmentLists.at(x, y)) objects.insert(f.object);
      for (const auto& [object, cover] : opaqueCover)
        if (cover.fetch(x, y).r >= 0.0f) objects.insert(object);
      return objects;
    };
    int differing = 0, offEdge = 0;
    double worst = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::vec4 a = abuffer.finalFloat.fetch(x, y), b = raycast.finalFloat.fetch(x, y);
        double d = 0;
        for (int k = 0; k < 3; ++k) d = std::max(d, double(std::abs(a[k] - b[k])));
        if (d <= 1e-5) continue;
        ++differing;
        worst = std::max(worst, d);
        bool edge = false;
        const auto here = objectsAt(x, y);
        for (int dy = -1; dy <= 1 && !edge; ++dy)
          for (int dx = -1; dx <= 1 && !edge; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx >= 0 && ny >= 0 && nx < w && ny < h && objectsAt(nx, ny) != here) edge = true;
          }
        if (!edge) {
          ++offEdge;
          WARN(tools::sceneName(path) << ": pixel " << x << "," << y << " differs by " << d << " away from any edge");
        }
      }
    const double share = double(differing) / double(w * h);
    INFO(tools::sceneName(path) << ": " << differing << " of " << w * h << " pixels (" << 100 * share
                                << " %) differ by more than 1e-5, worst " << worst);
    CHECK(share <= 0.001);
    CHECK(offEdge == 0);
  }
}
