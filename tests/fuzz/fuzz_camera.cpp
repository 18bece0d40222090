// Bytes → a camera (position, target, up, fov_y, near, far as fp32 bit patterns) and a frame size
// → parseScene over a few particles → both ground truths' inputs: the rasterizer's projection and
// the ray cast's rays. A camera the scene reader accepts must either be refused by the projection
// at the frame's aspect (std::invalid_argument, as `render` reports it) or render with both the
// rasterizer (wsum) and the ray cast into finite pixels — the rasterizer may refuse a frame whose
// clip coordinates it cannot clip within a pixel (RasterPrecisionError); anything else is a finding.
// The depth precision check that loadScene adds runs on every camera too.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "oitref/oit/method.h"
#include "oitref/core/renderer.h"
#include "oitref/oit/scene.h"
#include "oitref/oit/scene_geometry.h"

namespace {

std::string number(float v) {
  if (std::isnan(v)) return "1e39";  // beyond fp32: the reader's own refusal
  if (std::isinf(v)) return v > 0 ? "1e39" : "-1e39";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", double(v));
  return text;
}

void requireFinite(const oitref::Image& image) {
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 4; ++c)
        if (!std::isfinite(image.fetch(x, y)[c])) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr size_t kFloats = 12;
  if (size < kFloats * 4 + 2) return 0;
  float v[kFloats];
  std::memcpy(v, data, sizeof v);
  const int width = 1 + data[kFloats * 4] % 64, height = 1 + data[kFloats * 4 + 1] % 64;
  auto vec3 = [&](int i) { return "[" + number(v[i]) + "," + number(v[i + 1]) + "," + number(v[i + 2]) + "]"; };
  const std::string text = "{\"resolution\":[" + std::to_string(width) + "," + std::to_string(height) +
                           "],\"camera\":{\"position\":" + vec3(0) + ",\"target\":" + vec3(3) + ",\"up\":" + vec3(6) +
                           ",\"fov_y\":" + number(v[9]) + ",\"near\":" + number(v[10]) + ",\"far\":" + number(v[11]) +
                           "},\"objects\":[{\"type\":\"particle\",\"count\":6,\"seed\":3,\"color_override\":[0.8,0.3,0.2,0.5],"
                           "\"scale\":1,\"size\":0.6}]}";
  oitref::Scene scene;
  try {
    scene = oitref::parseScene(text, "fuzz_camera.json");
  } catch (const oitref::SceneError&) {
    return 0;
  }
  static oitref::Renderer renderer(oitref::RendererOptions{1, 0});
  const oitref::SceneGeometry geometry = oitref::buildSceneGeometry(scene);
  (void)oitref::depthPrecisionProblem(geometry);  // loadScene's depth check (a reason or "", never a fault)
  const oitref::FrameContext context{scene, geometry, scene.width, scene.height, oitref::exactProfile(), renderer, uint64_t(1) << 30};
  try {
    (void)scene.camera.projection(float(scene.width) / float(scene.height));
  } catch (const std::invalid_argument&) {
    return 0;  // refused at this aspect, before any frame
  }
  requireFinite(oitref::makeMethod("raycast")->render(context).finalFloat);
  try {
    requireFinite(oitref::makeMethod("wsum")->render(context).finalFloat);
  } catch (const oitref::RasterPrecisionError&) {  // zoomed beyond what fp32 clip coordinates can place
  }
  return 0;
}
