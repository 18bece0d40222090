// What a frame reports about its own work, typed: the figures that `oitref study`, `suite` and
// `stress` read and that `oitref render` prints. Each method sets the figures it produces; the
// others stay empty, so a reader can tell "not produced" from zero.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace oitref {

struct FrameStats {
  // The A-buffer's lists.
  std::optional<uint64_t> fragments;               // transparent fragments stored
  std::optional<uint32_t> depthComplexityMax;      // the most fragments of one pixel
  std::optional<double> depthComplexityMean;       // fragments per pixel of the frame
  std::optional<uint64_t> pixelsWithTransparency;  // pixels with at least one fragment
  std::optional<uint64_t> fragmentStorageBytes;    // the A-buffer's bands and kept lists (lists=keep)
  // Depth peeling (front to back, and dual).
  std::optional<int> peelingPasses;  // peeling passes drawn, the last one included
  std::optional<int> layersPeeled;   // front-to-back peeling: the passes that found a layer
  std::optional<bool> allLayersPeeled;
  std::string layersLeftBecause;  // why, when allLayersPeeled is false
  // Moment-based methods: reconstructions that fell back to the fragment's own layer.
  std::optional<uint64_t> momentFallbacks;
  // Sorted OVER: the transparent triangles sorted.
  std::optional<uint64_t> sortedTriangles;

  // One figure that is set: its key (snake case, as in JSON and Python), its printed name, and
  // its value.
  struct Entry {
    const char* key;
    const char* name;
    std::variant<uint64_t, int64_t, double, bool, std::string> value;
    std::string text() const;  // the value as `oitref render` prints it
  };
  // The figures that are set, in a fixed order.
  std::vector<Entry> entries() const;
  // The same as (name, text) lines: what `oitref render` prints.
  std::vector<std::pair<std::string, std::string>> lines() const;
  bool operator==(const FrameStats&) const = default;
};

}  // namespace oitref
