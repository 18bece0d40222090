// Every built-in scene with every method at 1920×1080, with one thread and with all threads:
// median frame time, fragments shaded per second and ns per fragment, including what the two
// ground truths (the A-buffer and the Embree ray cast) cost. Numbers are printed, never asserted.
//
//   oitref_scene_bench [--repeat N] [--threads N] [--scenes DIR] [--scene NAME] [--method NAME] [--size WxH]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "oitref/oit/method.h"
#include "tools/process_setup.h"
#include "tools/suite.h"

using namespace oitref;

namespace {

struct Timing {
  double ms = 0;
  uint64_t fragments = 0;
};

// Each frame takes its attachments (and the A-buffer its fragment storage) from the one before
// through an AttachmentPool, as an application keeps its buffers and as `render`, `study` and
// `glcheck scene --time` time frames: without it the A-buffer's frame at 1080p was mostly the
// kernel faulting in and zeroing 1.7 GB.
Timing measure(Method& method, const FrameContext& unpooled, int repeat) {
  AttachmentPool pool;
  FrameContext context = unpooled;
  context.pool = &pool;
  FrameResult frame = method.render(context);  // warm-up
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    pool.recycle(std::move(frame));
    const auto t0 = std::chrono::steady_clock::now();
    frame = method.render(context);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], frame.fragmentsShaded()};
}

}  // namespace

int main(int argc, char** argv) {
  oitref::tools::keepLargeAllocations();
  int repeat = 3, width = 1920, height = 1080;
  std::string scenesDir = "scenes", onlyScene, onlyMethod;
  std::vector<int> threadCounts = {1, int(std::max(1u, std::thread::hardware_concurrency()))};
  for (int i = 1; i < argc; ++i) {
    const bool more = i + 1 < argc;
    if (!std::strcmp(argv[i], "--repeat") && more) repeat = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--threads") && more) threadCounts = {std::max(1, std::atoi(argv[++i]))};
    else if (!std::strcmp(argv[i], "--scenes") && more) scenesDir = argv[++i];
    else if (!std::strcmp(argv[i], "--scene") && more) onlyScene = argv[++i];
    else if (!std::strcmp(argv[i], "--method") && more) onlyMethod = argv[++i];
    else if (!std::strcmp(argv[i], "--size") && more && std::sscanf(argv[++i], "%dx%d", &width, &height) == 2) {}
    else {
      std::fprintf(stderr, "usage: oitref_scene_bench [--repeat N] [--threads N] [--scenes DIR] [--scene NAME] "
                           "[--method NAME] [--size WxH]\n");
      return 2;
    }
  }
  if (threadCounts.size() == 2 && threadCounts[0] == threadCounts[1]) threadCounts.pop_back();
  std::printf("oitref scene benchmark, %dx%d, every method at its defaults, median of %d runs after a warm-up\n", width,
              height, repeat);
  std::printf("%-10s %-8s %7s %10s %12s %10s %9s\n", "scene", "method", "threads", "ms", "fragments", "Mfrag/s", "ns/frag");
  try {
    for (const std::string& path : tools::sceneFiles(scenesDir)) {
      const std::string name = tools::sceneName(path);
      if (!onlyScene.empty() && name != onlyScene) continue;
      Scene scene = loadScene(path);
      scene.width = width, scene.height = height;
      const SceneGeometry geometry = buildSceneGeometry(scene);
      for (const MethodInfo& info : allMethods()) {
        if (!onlyMethod.empty() && info.name != onlyMethod) continue;
        for (int threads : threadCounts) {
          Renderer renderer(RendererOptions{threads, 64});
          const FrameContext context{scene, geometry, width, height, exactProfile(), renderer, defaultMemoryLimit()};
          // The A-buffer's fragment budget is lifted to what the memory limit allows (dense at
          // 1920×1080 stores 53 M fragments, above the default 50 M).
          std::unique_ptr<Method> method =
              info.name == "abuffer" ? makeMethod(info.name, {{"max_fragments", "1000000000"}}) : makeMethod(info.name);
          Timing t;
          try {
            checkMemory(*method, width, height, geometry, defaultMemoryLimit());
            t = measure(*method, context, repeat);
          } catch (const std::exception& e) {
            std::printf("%-10s %-8s %7d skipped: %s\n", name.c_str(), info.name.c_str(), threads, e.what());
            continue;
          }
          const double perSecond = t.fragments ? double(t.fragments) / (t.ms * 1e-3) : 0;
          std::printf("%-10s %-8s %7d %10.1f %12llu %10.2f %9s\n", name.c_str(), info.name.c_str(), threads, t.ms,
                      (unsigned long long)t.fragments, perSecond / 1e6,
                      t.fragments ? std::to_string(int(std::lround(t.ms * 1e6 / double(t.fragments)))).c_str() : "-");
          std::fflush(stdout);
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "oitref_scene_bench: %s\n", e.what());
    return 2;
  }
  std::puts("fragments: shaded by all passes of a frame (the ray cast shades none; its time is Embree's BVH build and "
            "traversal plus the per-pixel sort)");
  return 0;
}
