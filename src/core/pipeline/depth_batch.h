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
// returns their count. `rounding`: the d16/d24 conversion's rule (encodeDepthAs).
using DepthBatchTest = int (*)(DepthBuffer& depth, int x, int y, const double* z, int n, int* passed);

DepthBatchTest depthBatchTest(DepthFormat format, CompareFunc func, bool writeMask,
                              UnormRounding rounding = UnormRounding::ExactNearestEven);
// A shader's own test (ShaderDepthTest): no writes, the stored depths read as the shader reads
// them (depthCodeAsFetched under `read`).
DepthBatchTest shaderDepthBatchTest(DepthFormat format, CompareFunc func, TextureFiltering read);

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

// The stored depths of a row segment in one summary, for draws that do not write depth (a GPU's
// hierarchical depth): the least and the greatest word, in the order the test compares them.
// `ordered` is false where that order is not the words' (D32F values outside [+0, 1]: negative,
// −0, NaN, above 1); the summary then decides nothing.
struct StoredDepthRange {
  uint32_t least = 0, greatest = 0;
  bool ordered = false;
};
StoredDepthRange storedDepthRange(const DepthBuffer& depth, int x, int y, int n);

// What the test gives every window z in [zLow, zHigh] against every stored depth of a range:
// the code farthest from passing against the stored value nearest to failing (all pass), or the
// code nearest to passing against the value farthest from it (all fail), as DepthRunAccepts
// and DepthRunRejects take them for each stored value. Null for the functions with no such bound
// (never, equal, notequal).
enum class RunVerdict { Undecided, AllPass, AllFail };
using DepthRangeVerdict = RunVerdict (*)(const StoredDepthRange& range, double zLow, double zHigh);

DepthRangeVerdict depthRangeVerdict(DepthFormat format, CompareFunc func);

}  // namespace oitref::detail
