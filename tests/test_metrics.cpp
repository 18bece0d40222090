// Image differences against hand-derived values.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "oitref/metrics.h"

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
