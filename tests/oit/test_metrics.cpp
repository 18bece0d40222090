// Image differences against hand-derived values.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "oitref/oit/metrics.h"

using namespace oitref;

namespace {

Image rgba32f(int w, int h) { return Image(makeFormat(FormatId::RGBA32F), w, h); }

}  // namespace

TEST_CASE("compareImages: RMSE, max, mean, PSNR and shares by hand", "[metrics]") {
  const Profile p = exactProfile();
  Image a = rgba32f(2, 1), b = rgba32f(2, 1);
  a.store(0, 0, {0.5f, 0.5f, 0.5f, 1.0f}, p);
  b.store(0, 0, {0.5f, 0.5f, 0.5f, 0.0f}, p);   // alpha is not colour: no difference
  a.store(1, 0, {0.25f, 0.0f, 1.0f, 1.0f}, p);
  b.store(1, 0, {0.0f, 0.5f, 1.0f, 1.0f}, p);   // differences 0.25, 0.5, 0
  const ImageDifference d = compareImages(a, b, 0.3);
  // squares: 0.0625 + 0.25 = 0.3125 over 6 samples
  CHECK(d.mse == Approx(0.3125 / 6).epsilon(1e-15));
  CHECK(d.rmse == Approx(std::sqrt(0.3125 / 6)).epsilon(1e-15));
  CHECK(d.meanAbs == Approx(0.75 / 6).epsilon(1e-15));
  CHECK(d.psnr == Approx(10 * std::log10(6 / 0.3125)).epsilon(1e-12));
  CHECK(d.maxAbs == 0.5);
  CHECK((d.maxX == 1 && d.maxY == 0));
  CHECK(d.pixelsDiffering == 1);
  CHECK(d.pixelsAbove == 1);
  CHECK(d.shareWithin() == 0.5);
  CHECK(compareImages(a, b, 0.5).pixelsAbove == 0);
}

TEST_CASE("compareImages: equal images, non-finite pixels, mismatched shapes", "[metrics]") {
  const Profile p = exactProfile();
  Image a = rgba32f(2, 2), b = rgba32f(2, 2);
  const ImageDifference same = compareImages(a, a, 0.0);
  CHECK(same.rmse == 0);
  CHECK(std::isinf(same.psnr));
  CHECK(same.maxX == -1);
  a.store(1, 1, {std::numeric_limits<float>::quiet_NaN(), 0, 0, 1}, p);
  b.store(0, 0, {1.0f, 0, 0, 1}, p);
  const ImageDifference d = compareImages(a, b, 0.5);
  CHECK(d.nonFinitePixels == 1);
  CHECK(d.mse == Approx(1.0 / 9));  // 3 finite pixels × 3 channels, one square of 1
  CHECK(d.shareWithin() == 0.5);    // one above, one non-finite
  CHECK(d.nonFiniteDiffering == 1);  // the NaN against a number
  CHECK(d.pixelsDiffering == 2);     // it and the finite pixel
  CHECK(d.differs());
  // The same non-finite value in both images is no difference; another one is.
  b.store(1, 1, {std::numeric_limits<float>::quiet_NaN(), 0, 0, 1}, p);
  CHECK(compareImages(a, b, 2.0).nonFiniteDiffering == 0);
  CHECK(!compareImages(a, b, 2.0).differs());
  b.store(1, 1, {std::numeric_limits<float>::infinity(), 0, 0, 1}, p);
  CHECK(compareImages(a, b, 2.0).nonFiniteDiffering == 1);
  a.store(1, 1, {-std::numeric_limits<float>::infinity(), 0, 0, 1}, p);
  CHECK(compareImages(a, b, 2.0).nonFiniteDiffering == 1);  // −inf against +inf
  CHECK(compareImages(a, a, 0.0).nonFiniteDiffering == 0);
  CHECK_THROWS_WITH(compareImages(a, rgba32f(2, 1), 0), Catch::Contains("size"));
  CHECK_THROWS_WITH(compareImages(a, Image(makeFormat(FormatId::R32F), 2, 2), 0), Catch::Contains("channel count"));
}

TEST_CASE("errorHeatmap: black where equal, white at the scale, green where non-finite", "[metrics]") {
  const Profile p = exactProfile();
  Image a = rgba32f(3, 1), b = rgba32f(3, 1);
  a.store(1, 0, {0.2f, 0, 0, 1}, p);
  a.store(2, 0, {std::numeric_limits<float>::infinity(), 0, 0, 1}, p);
  const Image map = errorHeatmap(a, b, 0.1);
  const uint8_t* equal = map.texel(0, 0);
  const uint8_t* saturated = map.texel(1, 0);
  const uint8_t* nonFinite = map.texel(2, 0);
  CHECK((equal[0] == 0 && equal[1] == 0 && equal[2] == 0 && equal[3] == 255));
  CHECK((saturated[0] == 255 && saturated[1] == 255 && saturated[2] == 255));
  CHECK((nonFinite[0] == 0 && nonFinite[1] == 255 && nonFinite[2] == 0));
}

// ---- ꟻLIP ------------------------------------------------------------------------------------
// The expected values below are derived by hand from the paper's formulas and published colour
// data, not from oitref's code: the sRGB transfer function, L* = 116·Y^(1/3) − 16 for greys
// (the sRGB matrix's Y row sums to 1, so a grey's Y is its linear value), and the CIELAB values
// of the sRGB primaries green (87.7347, −86.1827, 83.1793) and blue (32.2970, 79.1875, −107.8602)
// (D65, as tabulated by Lindbloom). Uniform images have no features and are unchanged by the
// normalised CSF filters, so there ΔE = ΔE_c exactly.

namespace {

Image uniformRgba8(int w, int h, float grey) {
  Image image(makeFormat(FormatId::RGBA8), w, h);
  image.clear({grey, grey, grey, 1}, exactProfile());
  return image;
}

double huntHyabGreenBlue() {
  const double lg = 87.7347, ag = -86.1827, bg = 83.1793, lb = 32.2970, ab = 79.1875, bb = -107.8602;
  const double dA = ag * lg / 100 - ab * lb / 100, dB = bg * lg / 100 - bb * lb / 100;
  return std::fabs(lg - lb) + std::sqrt(dA * dA + dB * dB);  // ≈ 203.3
}

// ΔE_c for two greys with lightness l1, l2 (a* = b* = 0, so the Hunt adjustment is moot).
double colourTermForGreys(double l1, double l2) {
  const double cmax = std::pow(huntHyabGreenBlue(), 0.7), c = std::pow(std::fabs(l1 - l2), 0.7);
  return c < 0.4 * cmax ? 0.95 / (0.4 * cmax) * c : 0.95 + (c - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
}

double lightnessOfSrgb(double v) {
  const double linear = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  return 116 * std::cbrt(linear) - 16;
}

}  // namespace

TEST_CASE("FLIP: identical images give zero everywhere", "[metrics][flip]") {
  Image a(makeFormat(FormatId::RGBA8), 24, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) a.store(x, y, {x / 23.0f, y / 15.0f, float((x * y) % 7) / 6, 1}, exactProfile());
  const FlipResult r = flip(a, a);
  CHECK(r.mean == 0);
  CHECK(r.max == 0);
}

TEST_CASE("FLIP: uniform images give the colour term of the paper's formula", "[metrics][flip]") {
  // Black against white: HyAB = 100, 100^0.7 = 25.12 is above p_c·c_max = 16.5, so ΔE lands in
  // (0.95, 1]: 0.9674.
  const FlipResult bw = flip(uniformRgba8(8, 8, 0), uniformRgba8(8, 8, 1));
  CHECK(colourTermForGreys(0, 100) == Approx(0.9674).margin(1e-4));
  CHECK(bw.mean == Approx(colourTermForGreys(0, 100)).margin(2e-4));
  CHECK(bw.max == Approx(bw.mean).margin(1e-12));
  // Greys 128 and 153 of 255: below p_c·c_max, on the linear part.
  const double l1 = lightnessOfSrgb(128 / 255.0), l2 = lightnessOfSrgb(153 / 255.0);
  const FlipResult greys = flip(uniformRgba8(8, 8, 128 / 255.0f), uniformRgba8(8, 8, 153 / 255.0f));
  CHECK(greys.mean == Approx(colourTermForGreys(l1, l2)).margin(2e-4));
  CHECK(greys.mean < 0.95);
  // Positive and negative weights cancel to rounding (~1e-17); the square root of q_f = 0.5
  // lifts that to ~1e-8.
  for (double f : greys.feature) CHECK(f == Approx(0).margin(1e-7));
}

TEST_CASE("FLIP: a black-to-white step has the feature term (1/√2)^0.5 at the step", "[metrics][flip]") {
  // Edge filter: positive weights sum to 1, negative to −1. At the pixels on either side of a
  // vertical step of height 1 in y, every positive weight sees one side and every negative
  // weight the other, so ‖edge‖ = 1; the y-direction response of a vertical step is 0. The point
  // filter's response there is below 1 (it sees the step through one half of a symmetric
  // kernel), and a uniform image has no features, so ΔE_f = (1/√2)^0.5 = 0.840896.
  const int w = 64, h = 8;
  Image step(makeFormat(FormatId::RGBA8), w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) step.store(x, y, glm::vec4(x < w / 2 ? 0.0f : 1.0f, x < w / 2 ? 0.0f : 1.0f, x < w / 2 ? 0.0f : 1.0f, 1), exactProfile());
  const FlipResult r = flip(step, uniformRgba8(w, h, 0));
  for (int y = 0; y < h; ++y) {
    CHECK(r.at(r.feature, w / 2 - 1, y) == Approx(std::pow(1 / std::sqrt(2.0), 0.5)).margin(1e-9));
    CHECK(r.at(r.feature, w / 2, y) == Approx(std::pow(1 / std::sqrt(2.0), 0.5)).margin(1e-9));
    // Far from the step (more than both filters' radii, 10 and 9 pixels) the images are
    // uniform black against black, and white against black.
    CHECK(r.at(r.error, 2, y) == Approx(0).margin(1e-12));
    CHECK(r.at(r.error, w - 3, y) == Approx(colourTermForGreys(0, 100)).margin(2e-4));
  }
  // The metric is symmetric in its two images.
  const FlipResult swapped = flip(uniformRgba8(w, h, 0), step);
  CHECK(swapped.mean == Approx(r.mean).epsilon(1e-12));
}

TEST_CASE("FLIP: display clamp, NaN as black, and bad input", "[metrics][flip]") {
  Image hdr = rgba32f(8, 8), one = rgba32f(8, 8), nan = rgba32f(8, 8);
  hdr.clear({5, 5, 5, 1}, exactProfile());
  one.clear({1, 1, 1, 1}, exactProfile());
  nan.clear({std::numeric_limits<float>::quiet_NaN(), 0, 0, 1}, exactProfile());
  CHECK(flip(hdr, one).max == 0);                           // both show as white
  CHECK(flip(nan, rgba32f(8, 8)).max == 0);                 // NaN shows as black
  CHECK_THROWS_WITH(flip(hdr, rgba32f(8, 4)), Catch::Contains("size"));
  CHECK_THROWS_WITH(flip(hdr, one, FlipOptions{0}), Catch::Contains("pixels per degree"));
}

TEST_CASE("Heatmap legend: the map on top, a colour bar from black to white under it", "[metrics]") {
  Image a = rgba32f(100, 20), b = rgba32f(100, 20);
  const Image map = errorHeatmapWithLegend(a, b, 0.25);
  REQUIRE(map.width() == 100);
  REQUIRE(map.height() > 20);
  const int barRow = map.height() - 20 - 4 - 5;  // inside the bar (window y counts from the bottom)
  const uint8_t* left = map.texel(0, barRow);
  const uint8_t* right = map.texel(99, barRow);
  CHECK((left[0] == 0 && left[1] == 0 && left[2] == 0));
  CHECK((right[0] == 255 && right[1] == 255 && right[2] == 255));
  const uint8_t* top = map.texel(50, map.height() - 1);  // the map's own top row: zero error
  CHECK((top[0] == 0 && top[1] == 0 && top[2] == 0));
}
