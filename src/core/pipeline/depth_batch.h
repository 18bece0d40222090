// Stage 5, the early depth test of a span: a batch of consecutive pixels of one row, tested and
// written in one call whose format, compare function and write mask were chosen once per draw
// (llvmpipe decides its depth code per state, too). The arithmetic is encodeDepthAs and
// depthTestPasses of oitref/core/depth.h, the rules the per-fragment test (FragmentStage::earlyTest,
// the oracle) uses; here the encoding runs over all lanes first, where the compiler can use
// vector instructions (the same IEEE operations per lane).
#pragma once

#include "oitref/core/depth.h"

namespace oitref::detail {

// Tests the window depths z[0, n) of pixels (x + i, y) against `depth`, writes those that pass
// when the draw writes depth, stores the indices i that passed in `passed` (ascending) and
// returns their count.
using DepthBatchTest = int (*)(DepthBuffer& depth, int x, int y, const double* z, int n, int* passed);

DepthBatchTest depthBatchTest(DepthFormat format, CompareFunc func, bool writeMask);

// Whether every pixel (x + i, y), i < n, fails the test for every window z in [zLow, zHigh]
// (pipeline/depth_bounds.h): then none of them passes, whatever its exact z. The depth codes are
// monotone in z, so the bound's code nearest to passing stands for all of them: zLow's for less
// and lequal, zHigh's for greater and gequal, compared by depthTestPassesAs with each stored
// depth. Null for the functions with no such bound (equal, notequal, always, never).
using DepthRunRejects = bool (*)(const DepthBuffer& depth, int x, int y, int n, double zLow, double zHigh);

DepthRunRejects depthRunRejects(DepthFormat format, CompareFunc func);

// The converse: whether every pixel (x + i, y), i < n, passes the test for every window z in
// [zLow, zHigh]; then each passes whatever its exact z. The bound's code farthest from passing
// stands for all: zHigh's for less and lequal, zLow's for greater and gequal; always passes
// everything. Null for the functions with no such bound (never, equal, notequal).
using DepthRunAccepts = DepthRunRejects;

DepthRunAccepts depthRunAccepts(DepthFormat format, CompareFunc func);

}  // namespace oitref::detail
