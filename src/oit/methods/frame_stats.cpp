// FrameStats (oitref/oit/frame_stats.h): its entries and printed lines.
#include "oitref/oit/frame_stats.h"

namespace oitref {
namespace {

template <typename T, typename Stored>
void add(std::vector<FrameStats::Entry>& out, const char* key, const char* name, const std::optional<T>& v) {
  if (v) out.push_back({key, name, Stored(*v)});
}

}  // namespace

std::string FrameStats::Entry::text() const {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::string>) return v;
        else if constexpr (std::is_same_v<T, bool>) return v ? "yes" : "no";
        else return std::to_string(v);
      },
      value);
}

std::vector<FrameStats::Entry> FrameStats::entries() const {
  std::vector<Entry> out;
  add<uint64_t, uint64_t>(out, "fragments", "fragments", fragments);
  add<uint32_t, uint64_t>(out, "depth_complexity_max", "depth complexity max", depthComplexityMax);
  add<double, double>(out, "depth_complexity_mean", "depth complexity mean", depthComplexityMean);
  add<uint64_t, uint64_t>(out, "pixels_with_transparency", "pixels with transparency", pixelsWithTransparency);
  add<uint64_t, uint64_t>(out, "fragment_storage_bytes", "fragment storage bytes", fragmentStorageBytes);
  add<int, int64_t>(out, "peeling_passes", "peeling passes", peelingPasses);
  add<int, int64_t>(out, "layers_peeled", "passes that peeled a layer", layersPeeled);
  add<bool, bool>(out, "all_layers_peeled", "all layers peeled", allLayersPeeled);
  if (allLayersPeeled && !*allLayersPeeled) out.push_back({"layers_left_because", "layers left because", layersLeftBecause});
  add<uint64_t, uint64_t>(out, "moment_fallbacks", "moment reconstructions that fell back", momentFallbacks);
  add<uint64_t, uint64_t>(out, "sorted_triangles", "sorted triangles", sortedTriangles);
  return out;
}

std::vector<std::pair<std::string, std::string>> FrameStats::lines() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const Entry& e : entries()) out.emplace_back(e.name, e.text());
  return out;
}

}  // namespace oitref
