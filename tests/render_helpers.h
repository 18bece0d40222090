// Small helpers for pipeline tests: geometry from window coordinates, coverage counting.
#pragma once

#include <vector>

#include "oitref/core/renderer.h"

namespace oitref::test {

// A vertex given in window coordinates (pixels, y up) with w = 1 for a width × height target.
inline glm::vec4 windowToClip(double x, double y, double z, int width, int height) {
  return {float(x / (width * 0.5) - 1.0), float(y / (height * 0.5) - 1.0), float(2.0 * z - 1.0), 1.0f};
}

inline Geometry windowTriangles(const std::vector<glm::dvec3>& points, int width, int height) {
  Geometry g;
  for (const auto& p : points) g.clipPositions.push_back(windowToClip(p.x, p.y, p.z, width, height));
  return g;
}

// How many fragments each pixel received: additive blending of 1 into an r32f target.
inline std::vector<float> coverageCount(Renderer& r, const Geometry& g, int width, int height,
                                        RasterState raster = {}, DepthState depth = {}) {
  Image count(makeFormat(FormatId::R32F), width, height);
  count.clear(glm::vec4(0), exactProfile());
  Framebuffer fb;
  fb.color[0] = &count;
  PipelineState st;
  st.raster = raster;
  st.depth = depth;
  st.blend[0] = BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::One);
  r.draw(fb, st, g, {[](const FragmentInput&, FragmentOutput& o) { o.write(0, glm::vec4(1.0f)); }});
  std::vector<float> out(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) out[size_t(y) * width + x] = count.fetch(x, y).r;
  return out;
}

}  // namespace oitref::test
