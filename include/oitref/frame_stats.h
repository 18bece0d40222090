// What a frame reports about its own work, typed: the figures that `oitref study`, `suite` and
// `stress` read and that `oitref render` prints. Each method sets the figures it produces; the
// others stay empty, so a reader can tell "not produced" from zero.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace oitref {

struct FrameStats {
  // The A-buffer's lists.
  std::optional<uint64_t> fragments;               // transparent fragments stored
  std::optional<uint32_t> depthComplexityMax;      // the most fragments of one pixel
  std::optional<double> depthComplexityMean;       // fragments per pixel of the frame
  std::optional<uint64_t> pixelsWithTransparency;  // pixels with at least one fragment
  std::optional<uint64_t> fragmentStorageBytes;    // the lists and their offsets
  // Depth peeling (front to back, and dual).
  std::optional<int> peelingPasses;  // peeling passes drawn, the last one included
  std::optional<int> layersPeeled;   // front-to-back peeling: the passes that found a layer
  std::optional<bool> allLayersPeeled;
  std::string layersLeftBecause;  // why, when allLayersPeeled is false
  // Moment-based methods: reconstructions that fell back to the fragment's own layer.
  std::optional<uint64_t> momentFallbacks;
  // Sorted OVER: the transparent triangles sorted.
  std::optional<uint64_t> sortedTriangles;

  // The figures that are set, as (name, value) in a fixed order: what `oitref render` prints.
  std::vector<std::pair<std::string, std::string>> lines() const;
  bool operator==(const FrameStats&) const = default;
};

}  // namespace oitref
