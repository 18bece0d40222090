// glcheck's raster mode: a few hundred random triangles, each drawn alone by the GL driver and by
// oitref into a small framebuffer of a D32F depth buffer and an RGBA32F target, compared pixel by
// pixel. The fragment shader writes (attribute, gl_FragCoord.z, 1 / gl_FragCoord.w, 1); the depth
// test is ALWAYS with writes on, so the depth buffer holds the rasterizer's own depth of every
// covered pixel. That separates what scene mode sees only mixed: which pixels a triangle covers
// (snapping and the fill rule), the depth it stores, and its interpolation, each against every
// raster rule oitref has. Its use beside llvmpipe is a check (bit-exact under raster=llvmpipe);
// through a GL trace it measures what another machine's GPU shares with those rules.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "glcheck/gl_context.h"

namespace oitref::glcheck {

struct RasterCheckOptions {
  int triangles = 400;   // spread over the generator's classes (raster_check.cpp)
  uint32_t seed = 1;
  int size = 64;         // the framebuffer: size × size pixels
  // oitref's rules compared, each a profile (the exact raster rule once with each fill convention).
  std::vector<std::string> profiles = {"exact", "llvmpipe"};
  // The profile whose rule must match in every pixel for exit 0; empty: report only.
  std::string require = "llvmpipe";
  bool requireCoverageOnly = false;  // the required rule must cover the same pixels; values reported
};

struct RasterCheckRow {
  std::string rule, triangleClass;
  uint64_t triangles = 0, glCovered = 0, oitrefCovered = 0;
  uint64_t coverageDiffers = 0, trianglesWithCoverageDiffering = 0;
  uint64_t both = 0;  // pixels both cover: the depth and interpolation shares are of these
  uint64_t depthEqual = 0, fragZEqual = 0, attributeEqual = 0, viewDepthEqual = 0;
  double depthMaxError = 0, attributeMaxError = 0, viewDepthMaxError = 0;  // largest |GL − oitref|
  bool allEqual() const {
    return coverageDiffers == 0 && depthEqual == both && fragZEqual == both && attributeEqual == both &&
           viewDepthEqual == both;
  }
};

struct RasterCheckResult {
  std::vector<RasterCheckRow> rows;  // per rule: one row per class, then "all"
  uint64_t glPixels = 0, glDepthIsFragZ = 0;  // the driver's stored depth against its own gl_FragCoord.z
  bool pass = true;                  // the required rule's "all" row is equal (or covers alike)
};

// Draws and compares; prints the tables to `out`. Throws on GL errors and unknown profiles.
RasterCheckResult runRasterCheck(const GlContext& context, const RasterCheckOptions& options, std::ostream& out);

}  // namespace oitref::glcheck
