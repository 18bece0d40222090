// The fragment stage's interpolation for a triangle: what beginTriangle proves once per triangle
// (flat attributes, the depth plane), the window depths of a run from that plane, and the
// attributes interpolated per fragment and per batch in lanes. The rest of the stage (spans,
// tests, shading, blending) is fragment_ops.cpp.
#include <algorithm>
#include <cstring>

#include "pipeline/fragment_ops.h"

namespace oitref::detail {

void FragmentStage::beginTriangle(const SetupTriangle& t, const float* planes) {
  triangle_ = &t;
  interpolation_ = &t.interpolation;
  planes_ = planes;
  if (llvmpipe_) return;  // the planes are all its fragments need
  if (depthRunRejects_ || depthRunAccepts_) depthBounds_.beginTriangle(t.interpolation);
  rejectSkip_ = rejectBackoff_ = 0;
  const int n = int(attributes_.size());
  for (int i = 0; i < 3; ++i) {
    const float* a = geometry_->vertexAttributes(t.vertexIndex[i]);
    for (int k = 0; k < n; ++k) vertexAttributes_[size_t(i * n + k)] = a[k];
  }
  const double* va = vertexAttributes_.data();
  flatAttributes_ = 0;
  for (int k = 0; k < std::min(n, 64); ++k)
    flatAttributes_ |= uint64_t(flatAttributeValue(va[k], va[n + k], va[2 * n + k])) << k;
  flatRowsWritten_ = false;
  flatProven_ = planeDepth_ = false;
  // The bound is proven for a triangle with any flat attribute: where only some are (a particle's
  // colour, not its uv), interpolateAttributesBatch then skips its check per batch.
  const bool allFlat = n > 0 && n <= 64 && flatAttributes_ == (n == 64 ? ~uint64_t(0) : (uint64_t(1) << n) - 1);
  if (n > 0 && flatAttributes_ != 0) {
    // The triangle's pixels in this stage's tile (rasterizeTile's rectangle), or all of them.
    PixelRect r = t.bounds;
    if (tile_.x1 > tile_.x0)
      r = {std::max(r.x0, tile_.x0), std::max(r.y0, tile_.y0), std::min(r.x1, tile_.x1), std::min(r.y1, tile_.y1)};
    const double ndc[4] = {ndcScaleX_, ndcOffsetX_, ndcScaleY_, ndcOffsetY_};
    RectangleBound bound;
    flatProven_ = !interpolation_->degenerate && barycentricsBoundedOn(*interpolation_, ndc, r, &bound);
    planeDepth_ = allFlat && planeDepthEligible_ && flatProven_ && windowDepthPlane(*interpolation_, bound, depthPlane_);
  }
  flatTriangle_ = allFlat && (flatEligible_ || planeDepth_) && flatProven_;
}

// Lanes past n compute columns beyond the run; their results are neither checked nor read.
bool FragmentStage::windowDepthsFromPlane(double yn, int start, int n) {
  // The plane and the NDC scale as locals: read through `this`, every group loaded them again
  // after its store into batchDepth_, which might have aliased them.
  const WindowDepthPlane p = depthPlane_;
  const double rowPart = p.b * yn + p.c, scale = ndcScaleX_, offset = ndcOffsetX_;
  float* const out = batchDepth_;
  lanes::i4 differ = {0, 0, 0, 0};
  // The columns as doubles, stepped by 4: integers, so each lane holds double(start + i) exactly,
  // as converting each column would (one add instead of a conversion and four adds per group).
  lanes::d4 column = lanes::d4{0.0, 1.0, 2.0, 3.0} + double(start);
  // Four pixels at a time; the lanes of the last four past the run compute pixels beyond it, never
  // read, and only they are masked out of the check (a mask in every step cost a fifth of the loop).
  const auto group = [&](int i) {
    const lanes::d4 xn = column * scale + offset;
    const lanes::d4 z = 0.5 * (p.a * xn + rowPart) + 0.5;
    const lanes::f4 low = lanes::convert<lanes::f4>(z - p.error), high = lanes::convert<lanes::f4>(z + p.error);
    lanes::i4 lowBits, highBits;  // bit patterns: +0 and −0 are not the same depth here
    std::memcpy(&lowBits, &low, sizeof low), std::memcpy(&highBits, &high, sizeof high);
    std::memcpy(out + i, &low, sizeof low);
    column += 4.0;
    return lanes::i4(lowBits != highBits);
  };
  int i = 0;
  for (; i + 4 <= n; i += 4) differ |= group(i);
  if (i < n) differ |= group(i) & (lanes::i4{0, 1, 2, 3} + i < n);
  return !(differ[0] | differ[1] | differ[2] | differ[3]);
}

void FragmentStage::interpolateAttributes(const double* b, float* out) const {
  const int n = int(attributes_.size());
  const double* va = vertexAttributes_.data();
  for (int k = 0; k < n; ++k) out[k] = interpolateAttribute(b[0], b[1], b[2], va[k], va[n + k], va[2 * n + k]);
}

// Lanes up to the next multiple of four past `count` compute from whatever b holds there; their
// results are never read.
uint64_t FragmentStage::interpolateAttributesBatch(const double* b0, const double* b1, const double* b2, int count,
                                                   float* out) const {
  const int n = int(attributes_.size());
  const double* va = vertexAttributes_.data();
  // The flat attributes are their vertices' value where every lane's B is below the bound
  // (flatAttributeValue; a NaN B fails the test), proven for the whole triangle in the tile
  // (flatProven_: the lanes past `count`, outside the span, do not matter then) or lane by lane.
  uint64_t flat = flatAttributes_;
  if (flat && !flatProven_) {
    typedef int64_t l4 __attribute__((vector_size(32)));
    const auto magnitude = [](lanes::d4 v) { return v < 0.0 ? -v : v; };
    l4 bounded = l4{} - 1;
    for (int j = 0; j < count; j += 4) {
      lanes::d4 c0, c1, c2;
      std::memcpy(&c0, b0 + j, sizeof c0), std::memcpy(&c1, b1 + j, sizeof c1), std::memcpy(&c2, b2 + j, sizeof c2);
      bounded &= (magnitude(c0) + magnitude(c1)) + magnitude(c2) < kFlatBarycentricBound;
    }
    if (!(bounded[0] & bounded[1] & bounded[2] & bounded[3])) flat = 0;
  }
  for (int k = 0; k < n; ++k) {
    float* row = out + size_t(k) * kBatch;
    if (k < 64 && (flat >> k & 1)) {
      std::fill_n(row, count, float(va[k]));
      continue;
    }
    const lanes::d4 a0 = lanes::splat<lanes::d4>(va[k]), a1 = lanes::splat<lanes::d4>(va[n + k]),
                    a2 = lanes::splat<lanes::d4>(va[2 * n + k]);
    for (int j = 0; j < count; j += 4) {
      lanes::d4 c0, c1, c2;
      std::memcpy(&c0, b0 + j, sizeof c0), std::memcpy(&c1, b1 + j, sizeof c1), std::memcpy(&c2, b2 + j, sizeof c2);
      const lanes::f4 a = lanes::convert<lanes::f4>(c0 * a0 + c1 * a1 + c2 * a2);  // interpolateAttribute's
      std::memcpy(row + j, &a, sizeof a);
    }
  }
  return flat;
}

}  // namespace oitref::detail
