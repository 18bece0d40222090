// Tests from the sources' printed formulas (issue 21): tiny scenes of full-screen layers whose
// expected colours are computed in double from a source's equations as printed, with every
// fragment's depth derived here from the camera (not taken from oitref's A-buffer or helpers).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "method_fixture.h"

namespace oitref::test {
namespace {

struct Layer {
  double distance;  // from the camera, along its view direction
  glm::vec4 color;  // straight RGBA
};

// Full-screen layers (the camera at z = 2 looks down −z) over an opaque background.
Scene layersAt(const std::vector<Layer>& layers, glm::vec3 background) {
  Scene s = layerScene(4, background);
  for (const Layer& l : layers) s.objects.push_back(quad({0.0f, 0.0f, float(2.0 - l.distance)}, 50.0f, l.color));
  return s;
}

// The window depth of a point at view distance d: glm::perspective's NDC z, (f + n)/(f − n) −
// 2fn/((f − n)·d), mapped by the default depth range, ½·z + ½ (GL 4.6 §13.8.1). The rasterizer
// rounds it to fp32 once (FragmentInput::depth).
double windowDepth(const Camera& c, double d) {
  const double n = c.nearPlane, f = c.farPlane;
  return 0.5 * ((f + n) / (f - n) - 2.0 * f * n / ((f - n) * d)) + 0.5;
}

// Rožek's thesis eq. 2.5–2.7 with weight W5 (α/z⁵), as printed: C = Σ c·α·w / Σ α·w (no clamp),
// T = Π(1 − α), and the pixel C·(1 − T) + C0·T. `clampDivisor` applies McGuire–Bavoil's
// clamp(Σα·w, 1e-4, 5e4) instead, listing 3's form.
glm::dvec3 wboitW5(const Scene& s, const std::vector<Layer>& layers, bool clampDivisor) {
  glm::dvec3 sum(0.0);
  double weights = 0.0, reveal = 1.0;
  for (const Layer& l : layers) {
    const double a = l.color.a, z = double(float(windowDepth(s.camera, l.distance)));
    const double w = a / std::pow(z, 5);
    sum += glm::dvec3(glm::vec3(l.color)) * a * w;
    weights += a * w;
    reveal *= 1.0 - a;
  }
  const double divisor = clampDivisor ? std::clamp(weights, 1e-4, 5e4) : weights;
  return sum / divisor * (1.0 - reveal) + glm::dvec3(s.background) * reveal;
}

}  // namespace

// Issue 21: McGuire–Bavoil's clamp was applied to the thesis's weights too. With a layer near the
// near plane, W5's Σα·w passes 5e4 and the clamp changes the colour; clamp=none is eq. 2.7.
TEST_CASE("printed formulas: WBOIT clamp=none is thesis eq. 2.7, clamp=mb McGuire–Bavoil's clamp", "[printed]") {
  const std::vector<Layer> layers = {{0.105, {0.9f, 0.2f, 0.1f, 0.4f}}, {0.8, {0.1f, 0.3f, 0.9f, 0.5f}},
                                     {1.9, {0.2f, 0.8f, 0.3f, 0.6f}}};
  const Scene s = layersAt(layers, {0.5f, 0.5f, 0.5f});
  for (const bool clamped : {false, true}) {
    const FrameResult f = render(s, "wboit", {{"weight", "az5"}, {"clamp", clamped ? "mb" : "none"}});
    const glm::dvec3 want = wboitW5(s, layers, clamped), other = wboitW5(s, layers, !clamped);
    // The printed forms differ here by far more than rounding: the test tells them apart.
    REQUIRE(glm::length(want - other) > 0.1);
    // fp32: W5 is five products and a division, the sums and the product round once per layer.
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) requireClose(f.finalFloat, x, y, want, 64 * kU32 * (1.0 + glm::length(want)), clamped ? "mb" : "none");
  }
}

}  // namespace oitref::test
