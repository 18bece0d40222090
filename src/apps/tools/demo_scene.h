// The pipeline's own demo scene, until the scene files and OIT methods exist: an opaque
// checkered floor and a seeded cloud of coloured translucent triangles seen in perspective,
// drawn three ways:
//   over_rgba8   unsorted OVER (src_alpha, one_minus_src_alpha) into RGBA8
//   over_rgba16f the same into RGBA16F
//   accum        a WBOIT-like two-target pass (RGBA16F additive, R16F multiplicative revealage)
//                resolved by a full-screen pass into RGBA8
// It exercises clipping (triangles cross the near plane), depth testing, blending on several
// formats, MRT and a full-screen pass.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oitref/core/image.h"
#include "oitref/core/renderer.h"

namespace oitref::tools {

struct DemoOptions {
  int width = 960, height = 540;
  int triangles = 64;
  uint32_t seed = 1;
  Profile profile;
};

struct DemoImage {
  std::string name;
  Image image;
};

struct DemoResult {
  std::vector<DemoImage> images;  // over_rgba8, over_rgba16f, accum_rgba16f, reveal_r16f, accum_resolved_rgba8
  std::vector<std::pair<std::string, DrawStats>> passes;
};

DemoResult renderDemo(Renderer& renderer, const DemoOptions& options);

}  // namespace oitref::tools
