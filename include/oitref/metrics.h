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

#include "oitref/image.h"

namespace oitref {

struct ImageDifference {
  size_t pixels = 0;
  size_t nonFinitePixels = 0;     // NaN or inf in either image
  size_t pixelsAbove = 0;         // e_p > threshold
  size_t pixelsDiffering = 0;     // e_p > 0
  double threshold = 0;
  double mse = 0, rmse = 0, psnr = 0, meanAbs = 0, maxAbs = 0;
  int maxX = -1, maxY = -1;       // where maxAbs is (GL window coordinates), −1 when equal
  double shareWithin() const { return pixels ? double(pixels - pixelsAbove - nonFinitePixels) / double(pixels) : 1.0; }
};

// Throws std::invalid_argument when sizes or channel counts differ.
ImageDifference compareImages(const Image& a, const Image& b, double threshold);

// An RGBA8 map of e_p / scaleMax through a perceptually ordered colour scale (black, blue,
// magenta, orange, yellow, white at ≥ 1); zero error is black, non-finite pixels are pure green.
Image errorHeatmap(const Image& a, const Image& b, double scaleMax);

}  // namespace oitref
