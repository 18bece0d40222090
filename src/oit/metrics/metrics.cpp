#include "oitref/oit/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "metrics/heatmap_legend.h"

namespace oitref {
namespace {

int colourChannels(const Format& f) { return std::min(f.channels, 3); }

void requireSameShape(const Image& a, const Image& b) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width()) + "x" + std::to_string(a.height()) +
                                " and " + std::to_string(b.width()) + "x" + std::to_string(b.height()));
  if (a.format().channels != b.format().channels)
    throw std::invalid_argument("images differ in channel count: " + std::to_string(a.format().channels) + " and " +
                                std::to_string(b.format().channels));
}

bool finite(const glm::vec4& v, int channels) {
  for (int c = 0; c < channels; ++c)
    if (!std::isfinite(v[c])) return false;
  return true;
}

// A channel's value as a kind: 0 a number, 1 NaN, 2 +inf, 3 −inf.
int kind(float v) { return std::isnan(v) ? 1 : std::isinf(v) ? (v > 0 ? 2 : 3) : 0; }

// Whether a pixel that is not finite in one image has another kind of value in the other in some
// channel (a NaN against a number, +inf against −inf, …).
bool nonFiniteDiffer(const Image& a, const Image& b, int x, int y, int channels) {
  const glm::vec4 va = a.fetch(x, y), vb = b.fetch(x, y);
  for (int c = 0; c < channels; ++c)
    if (kind(va[c]) != kind(vb[c])) return true;
  return false;
}

// e_p, or a negative value when the pixel is not finite in either image.
// Adds the pixel's squared and absolute channel differences to the sums.
double pixelError(const Image& a, const Image& b, int x, int y, int channels, double& squares, double& absSum) {
  const glm::vec4 va = a.fetch(x, y), vb = b.fetch(x, y);
  if (!finite(va, channels) || !finite(vb, channels)) return -1.0;
  double e = 0;
  for (int c = 0; c < channels; ++c) {
    const double d = double(va[c]) - double(vb[c]);
    e = std::max(e, std::fabs(d));
    squares += d * d;
    absSum += std::fabs(d);
  }
  return e;
}

}  // namespace

ImageDifference compareImages(const Image& a, const Image& b, double threshold) {
  requireSameShape(a, b);
  const int channels = colourChannels(a.format());
  ImageDifference d;
  d.threshold = threshold;
  d.pixels = size_t(a.width()) * size_t(a.height());
  double squares = 0, absSum = 0;
  size_t finitePixels = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const double e = pixelError(a, b, x, y, channels, squares, absSum);
      if (e < 0) {
        ++d.nonFinitePixels;
        if (nonFiniteDiffer(a, b, x, y, channels)) ++d.nonFiniteDiffering, ++d.pixelsDiffering;
        continue;
      }
      ++finitePixels;
      if (e > 0) ++d.pixelsDiffering;
      if (e > threshold) ++d.pixelsAbove;
      if (e > d.maxAbs) d.maxAbs = e, d.maxX = x, d.maxY = y;
    }
  const double samples = double(finitePixels) * channels;
  d.mse = samples > 0 ? squares / samples : 0.0;
  d.rmse = std::sqrt(d.mse);
  d.meanAbs = samples > 0 ? absSum / samples : 0.0;
  d.psnr = d.mse > 0 ? 10.0 * std::log10(1.0 / d.mse) : std::numeric_limits<double>::infinity();
  return d;
}

Image errorHeatmap(const Image& a, const Image& b, double scaleMax) {
  requireSameShape(a, b);
  const int channels = colourChannels(a.format());
  Image map(makeFormat(FormatId::RGBA8), a.width(), a.height());
  const Profile profile = exactProfile();
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      double squares = 0, absSum = 0;
      const double e = pixelError(a, b, x, y, channels, squares, absSum);
      glm::vec4 c(0, 1, 0, 1);  // non-finite
      if (e >= 0) heatmapColour(e <= 0 ? 0.0 : e / scaleMax, &c[0]);
      map.store(x, y, c, profile);
    }
  return map;
}

Image errorHeatmapWithLegend(const Image& a, const Image& b, double scaleMax) {
  return withLegend(errorHeatmap(a, b, scaleMax), scaleMax);
}

}  // namespace oitref
