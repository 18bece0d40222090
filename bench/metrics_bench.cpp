// What `oitref study` spends on each row after its frames: the image difference, ꟻLIP against the
// truth prepared once, and the row's two PNG files (the frame and its error heatmap). One thread,
// one scene's truth (the A-buffer) against each method's frame at the scene's size; median of
// --repeat runs after a warm-up. Numbers are printed, never asserted.
//
//   oitref_metrics_bench [--repeat N] [--scene FILE] [--size WxH]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "oitref/oit/image_io.h"
#include "oitref/oit/method.h"
#include "oitref/oit/metrics.h"
#include "tools/process_setup.h"

using namespace oitref;

namespace {

double medianMs(int repeat, const std::function<void()>& run) {
  run();  // warm-up
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  oitref::tools::keepLargeAllocations();  // as the study's process keeps them
  int repeat = 5, width = 0, height = 0;
  std::string scenePath = "scenes/dense.json";
  for (int i = 1; i < argc; ++i) {
    const bool more = i + 1 < argc;
    if (!std::strcmp(argv[i], "--repeat") && more) repeat = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--scene") && more) scenePath = argv[++i];
    else if (!std::strcmp(argv[i], "--size") && more && std::sscanf(argv[++i], "%dx%d", &width, &height) == 2) {}
    else {
      std::fprintf(stderr, "usage: oitref_metrics_bench [--repeat N] [--scene FILE] [--size WxH]\n");
      return 2;
    }
  }
  try {
    Scene scene = loadScene(scenePath);
    if (width > 0) scene.width = width, scene.height = height;
    const SceneGeometry geometry = buildSceneGeometry(scene);
    Renderer renderer(RendererOptions{1, 64});
    auto frame = [&](const char* name) {
      return makeMethod(name)->render(FrameContext{scene, geometry, scene.width, scene.height, exactProfile(), renderer});
    };
    const FrameResult truth = frame("abuffer");
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / "oitref_metrics_bench";
    std::filesystem::create_directories(folder);
    std::printf("oitref metrics benchmark: %s at %dx%d against the A-buffer, one thread, median of %d runs\n",
                scenePath.c_str(), scene.width, scene.height, repeat);
    std::printf("%-10s %12s %12s %12s %12s %12s\n", "method", "prepare ms", "difference", "flip ms", "png ms", "heatmap ms");
    double prepare = medianMs(repeat, [&] { FlipReference reference(truth.finalFloat); });
    const FlipReference reference(truth.finalFloat);
    for (const char* name : {"wboit", "mboit", "peel", "sorted"}) {
      const FrameResult test = frame(name);
      const double difference = medianMs(repeat, [&] { compareImages(test.finalFloat, truth.finalFloat, 1.0 / 255); });
      const double flipMs = medianMs(repeat, [&] { reference.compare(test.finalFloat); });
      const double png = medianMs(repeat, [&] { writeImage((folder / "frame.png").string(), test.final8); });
      const double heatmap = medianMs(repeat, [&] {
        writeImage((folder / "heatmap.png").string(), errorHeatmap(truth.finalFloat, test.finalFloat, 0.1));
      });
      std::printf("%-10s %12.2f %12.2f %12.2f %12.2f %12.2f\n", name, prepare, difference, flipMs, png, heatmap);
      prepare = 0;
    }
    std::filesystem::remove_all(folder);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "oitref_metrics_bench: %s\n", e.what());
    return 2;
  }
  return 0;
}
