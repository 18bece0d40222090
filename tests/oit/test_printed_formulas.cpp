// Tests from the sources' printed formulas (issue 21): tiny scenes of full-screen layers whose
// expected colours are computed in double from a source's equations as printed, with every
// fragment's depth derived here from the camera (not taken from oitref's A-buffer or helpers).
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Imath/half.h>

#include "method_fixture.h"

namespace oitref::test {
namespace {

struct Layer {
  double distance;  // from the camera, along its view direction
  glm::vec4 color;  // straight RGBA
};

// Full-screen layers (the camera at z = 2 looks down −z) over an opaque background, and an opaque
// full-screen quad at `opaqueDistance` when it is positive.
Scene layersAt(const std::vector<Layer>& layers, glm::vec3 background, double opaqueDistance = 0.0, int size = 4) {
  Scene s = layerScene(size, background);
  if (opaqueDistance > 0.0) {
    s.objects.push_back(quad({0.0f, 0.0f, float(2.0 - opaqueDistance)}, 50.0f, glm::vec4(background, 1.0f)));
    s.objects.back().transparentOverride = false;
  }
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
// `opaqueZ`: the thesis's adaptive form, W5 of z / z_s with z_s the opaque surface's depth.
glm::dvec3 wboitW5(const Scene& s, const std::vector<Layer>& layers, bool clampDivisor, double opaqueZ = 1.0,
                   double* divisor = nullptr) {
  glm::dvec3 sum(0.0);
  double weights = 0.0, reveal = 1.0;
  for (const Layer& l : layers) {
    const double a = l.color.a, z = double(float(windowDepth(s.camera, l.distance))) / opaqueZ;
    const double w = a / std::pow(z, 5);
    sum += glm::dvec3(glm::vec3(l.color)) * a * w;
    weights += a * w;
    reveal *= 1.0 - a;
  }
  if (divisor) *divisor = weights;
  return sum / (clampDivisor ? std::clamp(weights, 1e-4, 5e4) : weights) * (1.0 - reveal) + glm::dvec3(s.background) * reveal;
}

const std::vector<Layer> kThreeLayers = {{0.5, {0.9f, 0.2f, 0.1f, 0.2f}}, {1.0, {0.1f, 0.3f, 0.9f, 0.3f}},
                                         {1.5, {0.2f, 0.8f, 0.3f, 0.4f}}};
const glm::vec3 kBackground = {0.5f, 0.45f, 0.4f};

void requireEverywhere(const FrameResult& f, const glm::dvec3& want, double bound, const char* what) {
  for (int y = 0; y < f.finalFloat.height(); ++y)
    for (int x = 0; x < f.finalFloat.width(); ++x) requireClose(f.finalFloat, x, y, want, bound, what);
}

}  // namespace

// Thesis eq. 2.1 / Algorithm 2: C = Σ c·α + C0·(1 − Σα), the sums in RGBA16F (preset=thesis).
TEST_CASE("printed formulas: weighted sum, preset=thesis, is eq. 2.1", "[printed]") {
  const Scene s = layersAt(kThreeLayers, kBackground);
  glm::dvec3 sum(0.0);
  double alpha = 0.0;
  for (const Layer& l : kThreeLayers) sum += glm::dvec3(glm::vec3(l.color)) * double(l.color.a), alpha += l.color.a;
  const glm::dvec3 want = sum + glm::dvec3(kBackground) * (1.0 - alpha);
  // Each of the three products and sums rounds in fp16 (relative 2^-11); Σα = 0.9.
  requireEverywhere(render(s, "wsum", {{"preset", "thesis"}}), want, 16 * kU16, "wsum");
}

// Thesis eq. 2.2–2.4 / Algorithm 3 as printed: C = (Σcα / Σα)·(1 − (Σα/n)^n) + C0·(Σα/n)^n.
TEST_CASE("printed formulas: weighted average, preset=thesis, is eq. 2.2 as printed", "[printed]") {
  const Scene s = layersAt(kThreeLayers, kBackground);
  glm::dvec3 sum(0.0);
  double alpha = 0.0;
  for (const Layer& l : kThreeLayers) sum += glm::dvec3(glm::vec3(l.color)) * double(l.color.a), alpha += l.color.a;
  const double n = double(kThreeLayers.size()), t = std::pow(alpha / n, n);
  const glm::dvec3 want = sum / alpha * (1.0 - t) + glm::dvec3(kBackground) * t;
  requireEverywhere(render(s, "wavg", {{"preset", "thesis"}}), want, 64 * kU32, "wavg");
  // The published transmittance (1 − Σα/n)^n is another image: the preset is not the default.
  const double published = std::pow(1.0 - alpha / n, n);
  REQUIRE(std::abs(published - t) > 0.05);
}

// Thesis Algorithm 1: peeling composites the layers front to back, which is OVER back to front:
// C = Σ c_i·α_i·Π_{j<i}(1 − α_j) + C0·Π(1 − α_j). C2 and C3 are RGBA8 (preset=thesis), so each
// layer's (c·α, α) and each accumulation step round to 1/255.
TEST_CASE("printed formulas: depth peeling, preset=thesis, is the sorted composite within RGBA8 steps", "[printed]") {
  const Scene s = layersAt(kThreeLayers, kBackground);
  glm::dvec3 c = glm::dvec3(kBackground);
  for (auto l = kThreeLayers.rbegin(); l != kThreeLayers.rend(); ++l)  // farthest first
    c = glm::dvec3(glm::vec3(l->color)) * double(l->color.a) + c * (1.0 - double(l->color.a));
  const double steps = 2.0 * (double(kThreeLayers.size()) + 1.0);
  requireEverywhere(render(s, "peel", {{"preset", "thesis"}}), c, steps * 0.5 / 255.0, "peel");
}

namespace {

// Thesis Algorithm 5 (Hamburger4MSM) as printed, in double, with bias 0 (b' = b): solve the Hankel
// system for c, the roots z2 ≤ z3 of c3·z² + c2·z + c1, and the three cases of lines 4–6.
double hamburger4Msm(const std::array<double, 4>& b, double zf) {
  // Cholesky of [[1, b1, b2], [b1, b2, b3], [b2, b3, b4]] (b1 = b[0] …), then L·Lᵀ·c = (1, zf, zf²).
  const double a[3][3] = {{1.0, b[0], b[1]}, {b[0], b[1], b[2]}, {b[1], b[2], b[3]}};
  double l[3][3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j) {
      double sum = a[i][j];
      for (int k = 0; k < j; ++k) sum -= l[i][k] * l[j][k];
      l[i][j] = i == j ? std::sqrt(sum) : sum / l[j][j];
    }
  const double rhs[3] = {1.0, zf, zf * zf};
  double y[3], c[3];
  for (int i = 0; i < 3; ++i) {
    double sum = rhs[i];
    for (int k = 0; k < i; ++k) sum -= l[i][k] * y[k];
    y[i] = sum / l[i][i];
  }
  for (int i = 2; i >= 0; --i) {
    double sum = y[i];
    for (int k = i + 1; k < 3; ++k) sum -= l[k][i] * c[k];
    c[i] = sum / l[i][i];
  }
  const double disc = std::sqrt(c[1] * c[1] - 4.0 * c[2] * c[0]);
  double z2 = (-c[1] - disc) / (2.0 * c[2]), z3 = (-c[1] + disc) / (2.0 * c[2]);
  if (z2 > z3) std::swap(z2, z3);
  if (zf <= z2) return 0.0;
  if (zf <= z3) return (zf * z3 - b[0] * (zf + z3) + b[1]) / ((z3 - z2) * (zf - z2));
  return 1.0 - (z2 * z3 - b[0] * (z2 + z3) + b[1]) / ((zf - z2) * (zf - z3));
}

}  // namespace

// Thesis Algorithm 6 with eq. 2.8–2.11 as printed (preset=thesis): S_moment adds
// A·(z, z², z³, z⁴) and A = −ln(1 − α) for depths z in [0, 1]; S_weight is
// exp(−Hamburger4MSM(M/S, z, 0)·S), unclamped; the composite is eq. 2.9 with eq. 2.7. Layers spread
// over [0.17, 0.8] in depth, where the fp32 Hankel system is well conditioned (near 1, where most
// of a perspective depth range crowds, it is not: docs/rules.md).
TEST_CASE("printed formulas: MBOIT preset=thesis is Algorithms 5-6 with eq. 2.8-2.11", "[printed]") {
  const std::vector<Layer> layers = {{0.12, {0.9f, 0.2f, 0.1f, 0.3f}}, {0.2, {0.1f, 0.3f, 0.9f, 0.5f}},
                                     {0.5, {0.2f, 0.8f, 0.3f, 0.4f}}};
  const Scene s = layersAt(layers, kBackground);
  std::vector<double> z, absorbance;
  double total = 0.0;
  std::array<double, 4> moments{};
  for (const Layer& l : layers) {
    z.push_back(double(float(windowDepth(s.camera, l.distance))));
    absorbance.push_back(-std::log(1.0 - double(l.color.a)));
    total += absorbance.back();
    for (int k = 0; k < 4; ++k) moments[size_t(k)] += absorbance.back() * std::pow(z.back(), k + 1);
  }
  for (double& m : moments) m /= total;
  glm::dvec3 sum(0.0);
  double weights = 0.0, reveal = 1.0;
  for (size_t i = 0; i < layers.size(); ++i) {
    const double a = layers[i].color.a, w = std::exp(-hamburger4Msm(moments, z[i]) * total);
    sum += glm::dvec3(glm::vec3(layers[i].color)) * a * w;
    weights += a * w;
    reveal *= 1.0 - a;
  }
  const glm::dvec3 want = sum / weights * (1.0 - reveal) + glm::dvec3(kBackground) * reveal;
  // The default (biased moments, overestimation 0.25, depths in [−1, 1]) is another image.
  const FrameResult thesis = render(s, "mboit", {{"preset", "thesis"}}), plain = render(s, "mboit");
  REQUIRE(std::abs(double(plain.finalFloat.fetch(0, 0).r) - want.r) > 0.01);
  // fp32 moments and reconstruction: the absorbance within 1.3e-5 of exact (tests/oit/test_moments.cpp's
  // bound), so each weight within about 2e-5 relative for S ≈ 1.6, the average within 4e-5; 1e-4.
  requireEverywhere(thesis, want, 1e-4, "mboit thesis");
}

// Vallius's listings 4.3–4.9 (stochastic variant=vallius). "total" is Π(1 − α) through R16F
// blending (eq. 4.6). Per pass, layer i (nearest first) is the nearest survivor with probability
// α_i·Π_{j<i}(1 − α_j), none survives with probability T = Π(1 − α); the S passes overwrite, so a
// pixel shows the last pass's survivor, or 0 when no pass had one (probability T^S). The composite
// bg·T + t1·(1 − T) then has the expectation bg·T + Σ c_i·α_i·Π_{j<i}(1 − α_j)·(1 − T^S): the mean
// over 128×128 independent pixels is within 5 standard errors (each channel in [0, 1], so at most
// 0.5/128) of it. Averaging the passes, as Enderton et al. do, would give bg·T + Σ…·(1 − T)
// instead: far outside. As printed, the opaque depth is in neither framebuffer,
// so an opaque layer in front does not hide the transparent ones.
TEST_CASE("printed formulas: stochastic variant=vallius is listings 4.3-4.9 in expectation", "[printed]") {
  const int size = 128, samples = 8;
  const Scene s = layersAt(kThreeLayers, kBackground, 0.0, size);
  const FrameResult f = render(s, "stochastic", {{"variant", "vallius"}, {"samples", std::to_string(samples)}});
  double t = 1.0, t16 = 1.0;
  glm::dvec3 layersShare(0.0);
  for (const Layer& l : kThreeLayers) {
    layersShare += glm::dvec3(glm::vec3(l.color)) * double(l.color.a) * t;
    t *= 1.0 - double(l.color.a);
    t16 = double(Imath::half(float(t16 * (1.0 - double(l.color.a)))));  // each blend rounds to fp16
  }
  const glm::dvec3 expected = glm::dvec3(kBackground) * t + layersShare * (1.0 - std::pow(t, samples));
  const Image* total = nullptr;
  for (const auto& [name, image] : f.dump)
    if (name == "total") total = &image;
  REQUIRE(total);
  glm::dvec3 mean(0.0);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      REQUIRE(double(total->fetch(x, y).r) == t16);
      mean += glm::dvec3(glm::vec3(f.finalFloat.fetch(x, y))) / double(size * size);
    }
  const double bound = 5.0 * 0.5 / size;
  for (int k = 0; k < 3; ++k) CHECK(std::abs(mean[k] - expected[k]) < bound);
  const glm::dvec3 averaged = glm::dvec3(kBackground) * t + layersShare * (1.0 - t);
  CHECK(glm::length(averaged - expected) > 3 * bound);
  // An opaque quad in front of the layers: still mixed with them, bg·T + t1·(1 − T).
  const glm::vec3 opaque(0.1f, 0.9f, 0.1f);
  Scene covered = layersAt(kThreeLayers, kBackground, 0.0, size);
  covered.objects.push_back(quad({0.0f, 0.0f, 1.8f}, 50.0f, glm::vec4(opaque, 1.0f)));
  covered.objects.back().transparentOverride = false;
  const FrameResult c = render(covered, "stochastic", {{"variant", "vallius"}});
  double green = 0.0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) green += double(c.finalFloat.fetch(x, y).g) / double(size * size);
  CHECK(std::abs(green - (double(opaque.g) * t + layersShare.g * (1.0 - std::pow(t, 8)))) < bound);
  CHECK(render(covered, "stochastic").finalFloat.fetch(0, 0).g == opaque.g);  // Enderton et al.: hidden
}

// Issue 21: McGuire–Bavoil's clamp was applied to the thesis's weights too. With a layer near the
// near plane, W5's Σα·w passes 5e4 and the clamp changes the colour; preset=thesis (W5,
// clamp=none, RGBA32F/R32F) is eq. 2.5–2.7 as printed.
TEST_CASE("printed formulas: WBOIT preset=thesis is eq. 2.5-2.7, the default McGuire–Bavoil's clamp", "[printed]") {
  const std::vector<Layer> layers = {{0.105, {0.9f, 0.2f, 0.1f, 0.4f}}, {0.8, {0.1f, 0.3f, 0.9f, 0.5f}},
                                     {1.9, {0.2f, 0.8f, 0.3f, 0.6f}}};
  const Scene s = layersAt(layers, {0.5f, 0.5f, 0.5f});
  for (const bool clamped : {false, true}) {
    const FrameResult f = clamped ? render(s, "wboit", {{"weight", "az5"}}) : render(s, "wboit", {{"preset", "thesis"}});
    const glm::dvec3 want = wboitW5(s, layers, clamped), other = wboitW5(s, layers, !clamped);
    // The printed forms differ here by far more than rounding: the test tells them apart.
    REQUIRE(glm::length(want - other) > 0.1);
    // fp32: W5 is five products and a division, the sums and the product round once per layer.
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) requireClose(f.finalFloat, x, y, want, 64 * kU32 * (1.0 + glm::length(want)), clamped ? "mb" : "none");
  }
}

// Thesis §2.4: "each of the weight functions can be made adaptive by dividing the distance Z by
// Z_s". Every weight of a pixel then gains the factor z_s⁵, which cancels in eq. 2.7's quotient:
// unclamped, adaptive and plain W5 give the same colour up to rounding. With McGuire–Bavoil's
// clamp they differ where the plain weights pass 5e4 and the adaptive ones do not — near the
// camera, in front of a near opaque surface (the thesis's fig. 3.12). McGuire–Bavoil's weights
// have no adaptive form and are refused.
TEST_CASE("printed formulas: WBOIT adaptive W5 cancels in eq. 2.7 and shows only through the clamp", "[printed]") {
  const std::vector<Layer> layers = {{0.105, {0.9f, 0.2f, 0.1f, 0.4f}}, {0.11, {0.1f, 0.3f, 0.9f, 0.5f}}};
  const double opaqueDistance = 0.12;
  const Scene s = layersAt(layers, {0.5f, 0.5f, 0.5f}, opaqueDistance);
  const double zs = windowDepth(s.camera, opaqueDistance);
  double plainDivisor = 0.0, adaptiveDivisor = 0.0;
  const glm::dvec3 eq27 = wboitW5(s, layers, false, 1.0, &plainDivisor);
  const glm::dvec3 adaptiveEq27 = wboitW5(s, layers, false, zs, &adaptiveDivisor);
  const glm::dvec3 clamped = wboitW5(s, layers, true);
  REQUIRE(plainDivisor > 5e4);                                    // the plain weights are clamped
  REQUIRE((adaptiveDivisor > 1e-4 && adaptiveDivisor < 5e4));     // the adaptive ones are not
  REQUIRE(glm::length(eq27 - adaptiveEq27) < 1e-12);              // the cancellation, in double
  REQUIRE(glm::length(eq27 - clamped) > 0.1);
  struct Case {
    const char *adaptive, *clamp;
    glm::dvec3 want;
  };
  for (const Case& c : {Case{"false", "none", eq27}, Case{"true", "none", eq27}, Case{"true", "mb", eq27},
                        Case{"false", "mb", clamped}}) {
    const FrameResult f = render(s, "wboit", {{"weight", "az5"}, {"adaptive", c.adaptive}, {"clamp", c.clamp}});
    const std::string what = std::string("adaptive=") + c.adaptive + " clamp=" + c.clamp;
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) requireClose(f.finalFloat, x, y, c.want, 64 * kU32 * (1.0 + glm::length(c.want)), what.c_str());
  }
  for (const char* weight : {"mb7", "mb8", "mb9", "mb10"})
    CHECK_THROWS_WITH(render(s, "wboit", {{"weight", weight}, {"adaptive", "true"}}),
                      Catch::Contains("option 'adaptive'") && Catch::Contains(weight));
}

}  // namespace oitref::test
