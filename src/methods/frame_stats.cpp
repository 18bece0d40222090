// FrameStats (oitref/frame_stats.h): its printed lines.
#include "oitref/frame_stats.h"

namespace oitref {
namespace {

template <typename T>
void add(std::vector<std::pair<std::string, std::string>>& out, const char* name, const std::optional<T>& v) {
  if (v) out.emplace_back(name, std::to_string(*v));
}

}  // namespace

std::vector<std::pair<std::string, std::string>> FrameStats::lines() const {
  std::vector<std::pair<std::string, std::string>> out;
  add(out, "fragments", fragments);
  add(out, "depth complexity max", depthComplexityMax);
  add(out, "depth complexity mean", depthComplexityMean);
  add(out, "pixels with transparency", pixelsWithTransparency);
  add(out, "fragment storage bytes", fragmentStorageBytes);
  add(out, "peeling passes", peelingPasses);
  add(out, "passes that peeled a layer", layersPeeled);
  if (allLayersPeeled) out.emplace_back("all layers peeled", *allLayersPeeled ? "yes" : "no: " + layersLeftBecause);
  add(out, "moment reconstructions that fell back", momentFallbacks);
  add(out, "sorted triangles", sortedTriangles);
  return out;
}

}  // namespace oitref
