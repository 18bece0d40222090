// How far one image is from another: the numbers oitref reports when it compares a method with
// a ground truth, or oitref with a GPU. Both images are decoded exactly (Image::fetch) and
// compared in double on their colour channels (RGB, or as many as the format has; alpha is the
// presented target's bookkeeping, not colour).
//
//   per-pixel error  e_p = max over channels |a − b|
//   MSE              mean over pixels and channels of (a − b)²;  RMSE = √MSE
//   PSNR             10·log10(1 / MSE) for signals in [0, 1] (inf when equal)
// Pixels where either image holds NaN or ±inf are counted apart and left out of the sums, so one
// non-finite pixel cannot hide every other difference.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "oitref/core/image.h"

namespace oitref {

struct ImageDifference {
  size_t pixels = 0;
  size_t nonFinitePixels = 0;     // NaN or inf in either image
  size_t nonFiniteDiffering = 0;  // of those, the pixels where a channel differs in kind: a NaN or an
                                  // infinity against a number, or against the other non-finite value
  size_t pixelsAbove = 0;         // e_p > threshold
  size_t pixelsDiffering = 0;     // e_p > 0, or differing non-finite values
  double threshold = 0;
  double mse = 0, rmse = 0, psnr = 0, meanAbs = 0, maxAbs = 0;
  int maxX = -1, maxY = -1;       // where maxAbs is (GL window coordinates), −1 when equal
  double shareWithin() const { return pixels ? double(pixels - pixelsAbove - nonFinitePixels) / double(pixels) : 1.0; }
  // Whether the images differ beyond the threshold or in a non-finite value (`oitref compare`'s
  // exit status 1).
  bool differs() const { return pixelsAbove > 0 || nonFiniteDiffering > 0; }
};

// Throws std::invalid_argument when sizes or channel counts differ.
ImageDifference compareImages(const Image& a, const Image& b, double threshold);

// An RGBA8 map of e_p / scaleMax through a perceptually ordered colour scale (black, blue,
// magenta, orange, yellow, white at ≥ 1); zero error is black, non-finite pixels are pure green.
Image errorHeatmap(const Image& a, const Image& b, double scaleMax);

// The heatmap's colour for t = e / scaleMax in [0, 1] (clamped), as straight RGB in [0, 1]; the
// report draws its legends with it.
void heatmapColour(double t, float rgb[3]);

// A heatmap with its legend under it: a bar of the colour scale from 0 to scaleMax and the two
// end values written as numbers, so the PNG can be read on its own.
Image errorHeatmapWithLegend(const Image& a, const Image& b, double scaleMax);

// LDR ꟻLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild, "FLIP: A
// Difference Evaluator for Alternating Images", HPG 2020): the perceived difference between two
// images shown on a display, per pixel in [0, 1]. Both images are taken as what a display shows:
// their RGB values clamped to [0, 1] (NaN as 0) and read as sRGB-encoded. The steps, in the
// paper's order, are documented in src/oit/metrics/flip.cpp.
struct FlipOptions {
  // Pixels per degree of visual angle: a 0.7 m wide 3840-pixel monitor seen from 0.7 m, the
  // paper's default.
  double pixelsPerDegree = 0.7 * 3840 / 0.7 * 3.14159265358979323846 / 180;
};
struct FlipResult {
  int width = 0, height = 0;
  // Row-major, row 0 = image row y = 0 (GL window coordinates, like Image).
  std::vector<double> error;    // ΔE = ΔE_c^(1 − ΔE_f)
  std::vector<double> colour;   // ΔE_c, the colour pipeline
  std::vector<double> feature;  // ΔE_f, the feature pipeline
  double mean = 0, max = 0;     // of `error`
  double at(const std::vector<double>& map, int x, int y) const { return map[size_t(y) * width + x]; }
};
// Throws std::invalid_argument when sizes or channel counts differ.
FlipResult flip(const Image& reference, const Image& test, const FlipOptions& options = {});
// One reference prepared once for many comparisons (a study compares every method's frame with
// one ground truth): compare(test) is flip(reference, test, options), bit for bit.
class FlipReference {
 public:
  explicit FlipReference(const Image& reference, const FlipOptions& options = {});
  FlipResult compare(const Image& test) const;

 private:
  struct Prepared;
  std::shared_ptr<const Prepared> prepared_;
};
// The ꟻLIP error map through the heatmap's colour scale (1 is white), with its legend.
Image flipHeatmapWithLegend(const FlipResult& result);

}  // namespace oitref
