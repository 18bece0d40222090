// Behaviours the papers describe, reproduced and pinned down.
#include <catch2/catch.hpp>

#include <Imath/half.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "methods/methods.h"
#include "methods/moment_math.h"
#include "oitref/oit/frame.h"
#include "oitref/oit/method.h"

using namespace oitref;

namespace {

TriangleMesh bigQuad() {
  TriangleMesh m;
  m.positions = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
  m.colors.assign(4, glm::vec4(1.0f));
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

// `layers` screen-filling quads of colour `color` stacked from depth `nearest` backwards.
Scene stack(int layers, glm::vec4 color, float nearest, float spacing) {
  Scene s;
  s.width = 8;
  s.height = 8;
  s.background = {1.0f, 1.0f, 1.0f};
  s.camera.position = {0, 0, 0};
  s.camera.target = {0, 0, -1};
  s.camera.nearPlane = 0.05f;
  for (int i = 0; i < layers; ++i) {
    SceneObject o;
    o.mesh = bigQuad();
    o.position = {0, 0, -(nearest + spacing * float(i))};
    o.scale = 10.0f * (nearest + spacing * float(i));
    o.colorOverride = color;
    s.objects.push_back(o);
  }
  return s;
}

FrameResult render(const Scene& scene, const std::string& method, const std::map<std::string, std::string>& options) {
  Renderer r(RendererOptions{1, 8});
  return SceneFrames(scene, r).render(*makeMethod(method, options));
}

const Image& dumped(const FrameResult& f, const std::string& name) {
  for (const auto& [n, image] : f.dump)
    if (n == name) return image;
  throw std::logic_error("no attachment " + name);
}

}  // namespace

TEST_CASE("known: weighted sum darkens and leaves the gamut at high alpha (thesis §3.1)", "[known]") {
  // Four layers of α = 0.9 over white: Σα = 3.6, so the background weight 1 − Σα = −2.6.
  const FrameResult wsum = render(stack(4, {0.8f, 0.5f, 0.2f, 0.9f}, 1.0f, 0.5f), "wsum", {{"accum", "rgba32f"}});
  const glm::vec4 c = wsum.finalFloat.fetch(4, 4);
  // Σ c·α = 3.6·(0.8, 0.5, 0.2), plus 1·(1 − 3.6).
  CHECK(c.r == Approx(2.88 - 2.6).margin(1e-5));
  CHECK(c.b == Approx(0.72 - 2.6).margin(1e-5));
  CHECK(c.b < 0.0f);  // out of gamut: negative
  const FrameResult truth = render(stack(4, {0.8f, 0.5f, 0.2f, 0.9f}, 1.0f, 0.5f), "abuffer", {});
  CHECK(c.r < truth.finalFloat.fetch(4, 4).r);  // darker than the right answer
}

TEST_CASE("known: WBOIT fp16 accumulation overflows to inf after about 22 near, opaque layers", "[known]") {
  // mb7 weights are clamped at 3e3 for view depths below about 0.289, so each layer of α = 0.99 adds
  // α·w = 0.99·(0.99·3e3) ≈ 2940 to accum.a; fp16 holds at most 65504. The first layer count
  // whose sum rounds past it is predicted by adding in Imath's half, independently.
  const float alpha = 0.99f;
  const float w = alpha * 3e3f, add = alpha * w;
  half sum(0.0f);
  int firstInf = 0;
  for (int n = 1; n <= 64 && !firstInf; ++n) {
    sum = half(float(sum) + add);
    if (sum.isInfinity()) firstInf = n;
  }
  REQUIRE(firstInf >= 20);
  REQUIRE(firstInf <= 24);
  for (int layers : {firstInf - 1, firstInf}) {
    const FrameResult wboit = render(stack(layers, {0.3f, 0.6f, 0.9f, alpha}, 0.1f, 0.004f), "wboit",
                                     {{"accum", "rgba16f"}, {"weight", "mb7"}});
    const float a = dumped(wboit, "accum").fetch(4, 4).a;
    INFO(layers << " layers: accum.a = " << a << " (first inf predicted at " << firstInf << ")");
    CHECK(std::isinf(a) == (layers == firstInf));
  }
  // What the image shows: in fp16 the blue sum (0.9·2940 per layer) overflows too, and
  // inf / clamp(accum.a, 1e-4, 5e4) stays inf. In fp32 nothing overflows, but accum.a ≈ 79 400
  // exceeds the composite's upper clamp 5e4, so the average colour comes out 79 400/5e4 ≈ 1.59
  // times too bright: the clamp of McGuire–Bavoil listing 3 itself is wrong past 5e4.
  const Scene deep = stack(firstInf + 4, {0.3f, 0.6f, 0.9f, alpha}, 0.1f, 0.004f);
  const FrameResult broken = render(deep, "wboit", {{"accum", "rgba16f"}, {"weight", "mb7"}});
  const FrameResult fine = render(deep, "wboit", {{"accum", "rgba32f"}, {"weight", "mb7"}});
  const FrameResult truth = render(deep, "abuffer", {});
  const glm::vec4 shown = broken.finalFloat.fetch(4, 4), right = truth.finalFloat.fetch(4, 4), f32 = fine.finalFloat.fetch(4, 4);
  WARN("WBOIT mb7, " << firstInf + 4 << " layers: fp16 accumulation shows " << shown.r << "," << shown.g << "," << shown.b
                     << ", fp32 " << f32.r << "," << f32.g << "," << f32.b << ", A-buffer " << right.r << "," << right.g << ","
                     << right.b);
  CHECK(std::isinf(shown.b));
  CHECK(right.r == Approx(0.3).margin(1e-5));
  const double total = double(firstInf + 4) * double(add);
  CHECK(f32.r == Approx(0.3 * total / 5e4).epsilon(1e-4));
}

TEST_CASE("known: MBOIT's guards — α = 1, one layer without bias, nearly clear layers", "[known][mboit]") {
  // One layer and β = 0: the Hankel matrix has rank one; the reconstruction falls back to the
  // fragment's own layer instead of dividing by zero.
  const float oneLayer[4] = {0.3f, 0.09f, 0.027f, 0.0081f};  // z = 0.3 exactly
  const float a = methods::powerMomentAbsorbance(4, oneLayer, 0.3f, 0.0f, methods::powerBiasVector(4, false), 0.25f);
  CHECK(std::isfinite(a));
  CHECK(a == 0.25f);
  // α = 1 layers (b0 would be infinite) and α ≈ 0 layers (b0 below the threshold): finite output
  // that matches the A-buffer where it must — full cover, and (almost) no cover.
  for (float alpha : {1.0f, 1e-9f}) {
    const Scene s = stack(5, {0.2f, 0.4f, 0.6f, alpha}, 1.0f, 0.5f);
    const FrameResult mboit = render(s, "mboit", {}), truth = render(s, "abuffer", {});
    const glm::vec4 got = mboit.finalFloat.fetch(4, 4), want = truth.finalFloat.fetch(4, 4);
    INFO("alpha " << alpha << ": mboit " << got.r << "," << got.g << "," << got.b << ", A-buffer " << want.r << "," << want.g << "," << want.b);
    for (int k = 0; k < 3; ++k) {
      CHECK(std::isfinite(got[k]));
      CHECK(got[k] == Approx(want[k]).margin(1e-5));
    }
  }
}

TEST_CASE("known: the camera is glm::lookAt and glm::perspective", "[known]") {
  Camera c;
  c.position = {1, 2, 3};
  c.target = {0, 0.5f, -1};
  c.fovYDegrees = 63.0f;
  c.nearPlane = 0.25f;
  c.farPlane = 80.0f;
  const glm::mat4 ours = c.projection(1.5f), glm = glm::perspective(glm::radians(63.0f), 1.5f, 0.25f, 80.0f);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) CHECK(ours[i][j] == Approx(glm[i][j]).epsilon(2e-7).margin(1e-30));
  CHECK(c.view() == glm::lookAt(c.position, c.target, c.up));
}
