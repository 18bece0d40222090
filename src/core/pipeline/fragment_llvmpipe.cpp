// The fragment stage's interpolation under raster=llvmpipe: each fragment's window z, 1/w and
// attributes from the triangle's fp32 planes (llvmpipe_setup.h), at its integer pixel
// coordinates, as llvmpipe's generated fragment shader computes them (lp_bld_interp.c,
// attribs_update_simple). The tests, the shader and blending are fragment_ops.cpp's.
#include <algorithm>
#include <numeric>

#include "pipeline/fragment_ops.h"
#include "pipeline/llvmpipe_setup.h"

namespace oitref::detail {

void FragmentStage::llvmpipeBatch(int y, int start, int n) {
  const float* zPlane = planes_;
  const float* wPlane = planes_ + 3;
  const float fy = float(y);
  float z[kBatch], w[kBatch];
  double windowZ[kBatch];
  for (int i = 0; i < n; ++i) {
    const float fx = float(start + i);
    // The polygon offset, 0 here, is added to z (lp_bld_interp.c): +0 where z is −0.
    z[i] = llvmpipePlaneAt(zPlane, fx, fy, fused_) + 0.0f;
    w[i] = llvmpipePlaneAt(wPlane, fx, fy, fused_);
    windowZ[i] = z[i];
  }
  counters_.rasterized += uint64_t(n);
  int alive[kBatch];
  int count = n;
  if (earlyDepthTest_ || earlyReject_) {
    count = depthBatchTest_(*fb_.depth, start, y, windowZ, n, alive);
    counters_.depthFailed += uint64_t(n - count);
  } else {
    std::iota(alive, alive + n, 0);
  }
  if (discardBatchTest_ && count > 0) count = keepPassingDiscardTest(y, start, n, windowZ, alive, count);
  const int attributes = int(attributes_.size());
  for (int j = 0; j < count; ++j) {
    const int i = alive[j];
    const float fx = float(start + i);
    const float oow = 1.0f / w[i];  // lp_build_rcp: a division
    batchX_[j] = start + i;
    batchZ_[j] = windowZ[i];
    batchDepth_[j] = z[i];
    batchViewDepth_[j] = oow;  // the shaders' 1 / gl_FragCoord.w
    for (int k = 0; k < attributes; ++k)
      batchAttributes_[size_t(k) * kBatch + size_t(j)] = llvmpipePlaneAt(planes_ + 6 + 3 * k, fx, fy, fused_) * oow;
  }
  if (program_->batch) {
    batchUniform_ = 0;
    shadeAndBlendBatch(y, count, count == n);
    return;
  }
  int blended = 0;
  for (int j = 0; j < count; ++j) {
    FragmentInput in;
    fillInput(in, batchX_[j], y, batchZ_[j], double(batchViewDepth_[j]));
    for (int k = 0; k < attributes; ++k) attributes_[size_t(k)] = batchAttributes_[size_t(k) * kBatch + size_t(j)];
    if (shade(in, batchZ_[j], nullptr, output_, earlyDepthTest_ || earlyReject_)) {
      outputs_.store(blended, output_);
      blendX_[blended] = batchX_[j];
      blendIndex_[blended] = blended;
      ++blended;
    }
  }
  blendBatch(y, blended, blendX_, blendIndex_);
}

void FragmentStage::llvmpipeAttributesAt(int x, int y, int k, float out[2]) const {
  const float fx = float(x), fy = float(y);
  const float oow = 1.0f / llvmpipePlaneAt(planes_ + 3, fx, fy, fused_);
  for (int c = 0; c < 2; ++c) out[c] = llvmpipePlaneAt(planes_ + 6 + 3 * (k + c), fx, fy, fused_) * oow;
}

}  // namespace oitref::detail
