// glcheck's scene mode: a scene rendered by the GL version of a method (gl_methods.h) and by
// oitref's emulated pipeline under a profile, compared on the presented RGBA8 image and on the
// RGBA32F analysis copy, with every declared colour attachment compared bit for bit.
#pragma once

#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "glcheck/gl_context.h"
#include "glcheck/scene_timing.h"
#include "oitref/oit/metrics.h"

namespace oitref::glcheck {

struct SceneCheckOptions {
  std::vector<std::string> scenes;   // scene files
  std::vector<std::string> methods;  // empty: every method with a GL version
  std::map<std::string, std::string> methodOptions;  // given to every method checked (--set)
  int width = 0, height = 0;         // 0: the scene's resolution
  std::string profile = "llvmpipe";
  // Negative: the profile's default (docs/rules.md, "glcheck scene"). A profile whose raster rule
  // is llvmpipe's models the whole pipeline, so the check is bit-exact: tolerance 0, every pixel,
  // and every declared attachment and the RGBA32F copy bit-equal too. Other profiles interpolate
  // exactly where the driver does not, which flips RGBA8 roundings by one step: tolerance 1.5/255
  // (one step passes) at 99 % of the pixels.
  double tolerance = -1.0;           // per-pixel error allowed on the RGBA8 image
  double minShare = -1.0;            // pixels within tolerance a method must reach to pass
  uint64_t memoryLimit = UINT64_MAX;  // for oitref's frames (checkMemory)
  std::string heatmaps;              // folder for GL/oitref images and error heatmaps; empty: none
  int threads = 0;                   // oitref's renderer threads; 0: every hardware thread
  int timeRuns = 0;                  // > 0: also time each method side by side (scene_timing.h)
};

struct SceneCheckRow {
  std::string scene, method;
  ImageDifference presented, analysis;
  std::vector<std::pair<std::string, double>> attachmentsBitEqual;  // share of equal texels
  bool pass = false;
  std::optional<MethodTiming> timing;
};

// The options with the profile's defaults in place of the negative ones; `bitExact` where the
// resulting check is (tolerance 0 at 100 %).
SceneCheckOptions resolvedSceneCheckOptions(const SceneCheckOptions& options, bool* bitExact = nullptr);

// Renders and compares; prints a table per scene to `out`. Throws on GL or scene errors.
std::vector<SceneCheckRow> runSceneCheck(const GlContext& context, const SceneCheckOptions& options, std::ostream& out);

}  // namespace oitref::glcheck
