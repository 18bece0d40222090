// The fragment stage's interpolation under raster=llvmpipe: each fragment's window z, 1/w and
// attributes from the triangle's fp32 planes (llvmpipe_setup.h), at its integer pixel
// coordinates, as llvmpipe's generated fragment shader computes them (lp_bld_interp.c,
// attribs_update_simple). The tests, the shader and blending are fragment_ops.cpp's.
#include <algorithm>
#include <cstring>
#include <numeric>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "pipeline/fragment_ops.h"
#include "pipeline/llvmpipe_setup.h"

namespace oitref::detail {
namespace {

// A plane's values at pixels (x0 + i, y), i < n, into out[i] (llvmpipePlaneAt), and lanes up to
// the next multiple of 8 past n (never read): eight at a time with the CPU's fused multiply-add,
// which rounds as fmaf does, where it has one; one at a time otherwise.
using PlaneRow = void (*)(const float* plane, float y, int x0, int n, float* out);

void planeRowScalar(const float* plane, float y, int x0, int n, float* out, bool fused) {
  for (int i = 0; i < n; ++i) out[i] = llvmpipePlaneAt(plane, float(x0 + i), y, fused);
}
void planeRowFused(const float* plane, float y, int x0, int n, float* out) { planeRowScalar(plane, y, x0, n, out, true); }
void planeRowUnfused(const float* plane, float y, int x0, int n, float* out) { planeRowScalar(plane, y, x0, n, out, false); }

#if defined(__x86_64__)
[[gnu::target("avx2,fma")]] void planeRowFma(const float* plane, float y, int x0, int n, float* out) {
  const __m256 a0 = _mm256_set1_ps(plane[0]), dadx = _mm256_set1_ps(plane[1]), dady = _mm256_set1_ps(plane[2]);
  const __m256 fy = _mm256_set1_ps(y), eight = _mm256_set1_ps(8.0f);
  // The columns as floats: integers below 2^24, exact, so each step of 8 is too.
  __m256 x = _mm256_add_ps(_mm256_set1_ps(float(x0)), _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7));
  for (int i = 0; i < n; i += 8) {
    _mm256_storeu_ps(out + i, _mm256_fmadd_ps(dady, fy, _mm256_fmadd_ps(dadx, x, a0)));
    x = _mm256_add_ps(x, eight);
  }
}
#endif

PlaneRow planeRowFor(bool fused) {
  if (!fused) return planeRowUnfused;
#if defined(__x86_64__)
  static const bool fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (fma) return planeRowFma;
#endif
  return planeRowFused;
}

}  // namespace

void FragmentStage::llvmpipeBatch(int y, int start, int n) {
  const PlaneRow planeRow = planeRowFor(fused_);
  const float fy = float(y);
  alignas(32) float z[kBatch], w[kBatch];
  double windowZ[kBatch];
  planeRow(planes_, fy, start, n, z);
  planeRow(planes_ + 3, fy, start, n, w);
  for (int i = 0; i < n; ++i) {
    // The polygon offset, 0 here, is added to z (lp_bld_interp.c): +0 where z is −0.
    z[i] += 0.0f;
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
  if (count == 0) return;
  const int attributes = int(attributes_.size());
  alignas(32) float oow[kBatch];
  for (int i = 0; i < n; ++i) oow[i] = 1.0f / w[i];  // lp_build_rcp: a division
  // Each attribute's row for all n pixels, then the survivors moved to the front (j ≤ alive[j]).
  for (int k = 0; k < attributes; ++k) {
    float* row = batchAttributes_.data() + size_t(k) * kBatch;
    planeRow(planes_ + 6 + 3 * k, fy, start, n, row);
    for (int i = 0; i < n; ++i) row[i] *= oow[i];
    if (count < n)
      for (int j = 0; j < count; ++j) row[j] = row[alive[j]];
  }
  // The survivors' columns and depths (view depth: the shaders' 1 / gl_FragCoord.w); where every
  // pixel survived, the run's arrays as they are.
  if (count == n) {
    std::iota(batchX_, batchX_ + n, start);
    std::memcpy(batchZ_, windowZ, sizeof(double) * size_t(n));
    std::memcpy(batchDepth_, z, sizeof(float) * size_t(n));
    std::memcpy(batchViewDepth_, oow, sizeof(float) * size_t(n));
  } else {
    for (int j = 0; j < count; ++j) {
      const int i = alive[j];
      batchX_[j] = start + i;
      batchZ_[j] = windowZ[i];
      batchDepth_[j] = z[i];
      batchViewDepth_[j] = oow[i];
    }
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
