#include "pipeline/fragment_ops.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "util/round_to_float.h"

namespace oitref::detail {

FragmentStage::FragmentStage(Framebuffer& fb, const PipelineState& state, const FragmentProgram& program,
                             const Geometry* geometry, const PixelRect& viewport, uint32_t drawId)
    : fb_(fb), state_(state) {
  height_ = fb.height();
  llvmpipe_ = state.profile.raster == Rasterization::Llvmpipe;
  fused_ = state.profile.fma;
  depthRounding_ = llvmpipe_ ? UnormRounding::Fp32Product : UnormRounding::ExactNearestEven;
  blenders_.reserve(kMaxColorTargets);
  bool smallFloatBound = false;  // llvmpipe keeps denormals for the whole draw then
  for (int t = 0; t < kMaxColorTargets; ++t)
    if (fb.color[size_t(t)]) smallFloatBound |= isSmallFloatFormat(fb.color[size_t(t)]->format());
  for (int t = 0; t < kMaxColorTargets; ++t) {
    if (fb.color[size_t(t)]) boundTargets_ |= 1u << t;
    for (int i = 0; i < kBatch; ++i) allSources_[t][i] = outputs_.colors(t) + i;
    blenders_.emplace_back(fb.color[size_t(t)] ? fb.color[size_t(t)]->format() : Format{}, state.blend[size_t(t)],
                           state.blendConstant, state.profile, true, smallFloatBound);
  }
  // x_n = (x + ½ − vx)·(2/vw) − 1
  const double vw = viewport.x1 - viewport.x0, vh = viewport.y1 - viewport.y0;
  ndcScaleX_ = 2.0 / vw, ndcOffsetX_ = (0.5 - viewport.x0) * (2.0 / vw) - 1.0;
  ndcScaleY_ = 2.0 / vh, ndcOffsetY_ = (0.5 - viewport.y0) * (2.0 / vh) - 1.0;
  beginDraw(program, geometry, drawId);
}

void FragmentStage::beginDraw(const FragmentProgram& program, const Geometry* geometry, uint32_t drawId) {
  program_ = &program;
  geometry_ = geometry;
  drawId_ = drawId;
  triangle_ = nullptr;
  const DepthState& depth = state_.depth;
  earlyTests_ = program.earlyFragmentTests || !(program.mayDiscard || program.writesDepth);
  earlyDepthTest_ = earlyTests_ && fb_.depth != nullptr && depth.testEnabled;
  earlyReject_ = !earlyTests_ && program.pure && !program.writesDepth && fb_.depth != nullptr && depth.testEnabled;
  if (earlyDepthTest_) depthBatchTest_ = depthBatchTest(fb_.depth->format(), depth.func, depth.writeMask, depthRounding_);
  if (earlyReject_) depthBatchTest_ = depthBatchTest(fb_.depth->format(), depth.func, false, depthRounding_);
  depthRunRejects_ = earlyDepthTest_ || earlyReject_ ? depthRunRejects(fb_.depth->format(), depth.func) : nullptr;
  const bool testsDepth = fb_.depth != nullptr && depth.testEnabled;
  depthRunAccepts_ = earlyDepthTest_ && !depth.writeMask ? depthRunAccepts(fb_.depth->format(), depth.func) : nullptr;
  rangeVerdict_ = drawRangeVerdict();
  // Runs that surely pass the depth test need no test and no depth for it: positionSpan().
  const bool runsWithoutTest = program.batch && program.derivativesOf < 0 && earlyTests_ &&
                               program.discardTest.buffer == nullptr && (!testsDepth || depthRunAccepts_);
  flatEligible_ = runsWithoutTest && !program.readsDepth;
  planeDepthEligible_ = runsWithoutTest && program.readsDepth && !program.readsViewDepth;
  positionOnly_ = flatEligible_ && program.attributesRead == 0;
  // Tested without writing: the buffer is the shader's to read (const in the program).
  const ShaderDepthTest& discard = program.discardTest;
  const bool discardEarly = discard.buffer != nullptr && program.pure && !program.writesDepth;
  discardBuffer_ = discardEarly ? const_cast<DepthBuffer*>(discard.buffer) : nullptr;
  discardBatchTest_ = discardEarly ? shaderDepthBatchTest(discard.buffer->format(), discard.func, discard.read) : nullptr;
  skipsWindowDepth_ = program.batch && !program.readsDepth && earlyTests_ && discard.buffer == nullptr;
  // Only the attributes the shader reads are interpolated (FragmentProgram::attributesRead).
  size_t n = size_t(geometry ? geometry->attributeCount : 0);
  if (program.attributesRead >= 0) n = std::min(n, size_t(program.attributesRead));
  vertexAttributes_.assign(3 * n, 0.0);
  attributes_.assign(n, 0.0f);
  batchAttributes_.assign(size_t(kBatch) * n, 0.0f);
  flatTriangle_ = flatRowsWritten_ = flatProven_ = planeDepth_ = false;
  derivativesOf_ = program.derivativesOf;
  if (derivativesOf_ >= 0 && size_t(derivativesOf_) + 2 > n)
    throw std::logic_error("FragmentProgram::derivativesOf names attributes the draw does not interpolate");
}

void FragmentStage::quadDerivatives(int x, int y, double* out, int stride) const {
  const int n = int(attributes_.size()), k = derivativesOf_;
  if (llvmpipe_) {
    // llvmpipe's per quad (lp_bld_quad.c): top-right minus top-left, the row above minus top-left,
    // in fp32, for every pixel of the quad.
    const int x0 = x & ~1, y0 = y & ~1;
    float topLeft[2], topRight[2], above[2];
    llvmpipeAttributesAt(x0, y0, k, topLeft), llvmpipeAttributesAt(x0 + 1, y0, k, topRight);
    llvmpipeAttributesAt(x0, y0 + 1, k, above);
    for (int c = 0; c < 2; ++c) {
      out[c * stride] = double(topRight[c] - topLeft[c]);
      out[(2 + c) * stride] = double(above[c] - topLeft[c]);
    }
    return;
  }
  const double* va = vertexAttributes_.data();
  // Attributes k, k + 1 at pixel (px, py), as fragment() interpolates them there.
  auto at = [&](int px, int py, float st[2]) {
    double w, b0, b1, b2, z;
    interpolate(px, double(py) * ndcScaleY_ + ndcOffsetY_, w, b0, b1, b2, z);
    for (int c = 0; c < 2; ++c)
      st[c] = util::roundToFloat(double(interpolateAttribute(b0, b1, b2, va[k + c], va[n + k + c], va[2 * n + k + c])));
  };
  const int x0 = x & ~1, y0 = y & ~1;
  float left[2], right[2], bottom[2], top[2];
  at(x0, y, left), at(x0 + 1, y, right), at(x, y0, bottom), at(x, y0 + 1, top);
  for (int c = 0; c < 2; ++c) {
    out[c * stride] = double(right[c]) - double(left[c]);
    out[(2 + c) * stride] = double(top[c]) - double(bottom[c]);
  }
}

// Filled field by field in place: built as a temporary and copied, the copy's 16-byte loads of
// the temporary would wait for its narrower stores (no store forwarding).
void FragmentStage::fillInput(FragmentInput& in, int x, int y, double z, double w) const {
  in.x = x;
  in.y = y;
  in.fragCoord = {float(x) + 0.5f, float(y) + 0.5f};
  in.depth = float(z);
  in.viewDepth = float(w);
  in.frontFacing = triangle_ ? triangle_->frontFacing : true;
  in.primitiveId = triangle_ ? triangle_->primitiveId : 0;
  in.drawId = drawId_;
  in.attributes = attributes_.data();
  in.attributeCount = int(attributes_.size());
}

void FragmentStage::fragment(int x, int y) {
  if (llvmpipe_) return llvmpipeBatch(y, x, 1);
  if (interpolation_->degenerate) return;
  const double yn = double(y) * ndcScaleY_ + ndcOffsetY_;
  double w, b[3], z;
  interpolate(x, yn, w, b[0], b[1], b[2], z);
  FragmentInput in;
  fillInput(in, x, y, z, w);
  ++counters_.rasterized;
  process(in, z, b);
}

void FragmentStage::beginTile(const PixelRect& tile) {
  if (tile.y1 - tile.y0 > kMaxTileRows) throw std::logic_error("FragmentStage::beginTile: a tile taller than kMaxTileRows");
  tile_ = tile;
  std::fill(std::begin(rowRangesKnown_), std::end(rowRangesKnown_), uint64_t(0));
  rangeVerdict_ = drawRangeVerdict();
}

// The stored ranges hold while nothing writes depth: a draw that tests early or rejects early
// (depthRunRejects_ set) without writing depth, in a stage that knows its tile.
DepthRangeVerdict FragmentStage::drawRangeVerdict() const {
  if (!depthRunRejects_ || state_.depth.writeMask || tile_.x1 <= tile_.x0) return nullptr;
  return depthRangeVerdict(fb_.depth->format(), state_.depth.func);
}

const StoredDepthRange& FragmentStage::rowDepthRange(int y) {
  const int r = y - tile_.y0;
  uint64_t& known = rowRangesKnown_[r / 64];
  if (!(known >> (r % 64) & 1)) {
    rowRanges_[r] = storedDepthRange(*fb_.depth, tile_.x0, y, tile_.x1 - tile_.x0);
    known |= uint64_t(1) << (r % 64);
  }
  return rowRanges_[r];
}

RunVerdict FragmentStage::runVerdict(int y, int start, int n, double zLow, double zHigh, bool checkRuns, bool& read) {
  if (rangeVerdict_) {
    const RunVerdict v = rangeVerdict_(rowDepthRange(y), zLow, zHigh);
    if (v != RunVerdict::Undecided) return v;
  }
  if (!checkRuns) return RunVerdict::Undecided;
  if (depthRunRejects_ && depthRunRejects_(*fb_.depth, start, y, n, zLow, zHigh)) return read = true, RunVerdict::AllFail;
  if (depthRunAccepts_ && depthRunAccepts_(*fb_.depth, start, y, n, zLow, zHigh)) return read = true, RunVerdict::AllPass;
  return RunVerdict::Undecided;
}

void FragmentStage::span(int y, int x0, int x1) {
  if (llvmpipe_) {
    for (int start = x0; start < x1; start += kBatch) llvmpipeBatch(y, start, std::min(kBatch, x1 - start));
    return;
  }
  if (interpolation_->degenerate) return;
  const double yn = double(y) * ndcScaleY_ + ndcOffsetY_;
  if (positionOnly_ || flatTriangle_) {
    prefetchDepthRow(y + 2, x0, x1);
    return positionSpan(y, yn, x0, x1);
  }
  // Runs of kRejectRun pixels whose window z (depth_bounds.h) surely fails the depth test are
  // counted and skipped; those whose window z surely passes it (a draw that tests early without
  // writing depth) skip the per-fragment test; the rest are tested fragment by fragment. Each run
  // is one batch (kRejectRun = kBatch). The row's stored range decides without reading the run's
  // depths; where it cannot, the run's own depths are checked, unless backing off (below).
  const bool checkRuns = (depthRunRejects_ || depthRunAccepts_) && rejectSkip_ == 0;
  rejectSkip_ -= rejectSkip_ > 0;
  if (!rangeVerdict_) prefetchDepthRow(y + 2, x0, x1);  // with ranges, decided runs read no depths
  if (!rangeVerdict_ && !checkRuns) {
    for (int start = x0; start < x1; start += kBatch) spanBatch(y, yn, start, std::min(kBatch, x1 - start), false);
    return;
  }
  depthBounds_.beginRow(yn);
  bool read = false;
  for (int start = x0; start < x1; start += kRejectRun) {
    const int n = std::min(kRejectRun, x1 - start);
    double zLow, zHigh;
    const double first = double(start) * ndcScaleX_ + ndcOffsetX_, last = double(start + n - 1) * ndcScaleX_ + ndcOffsetX_;
    const RunVerdict v = depthBounds_.bound(first, last, zLow, zHigh) ? runVerdict(y, start, n, zLow, zHigh, checkRuns, read)
                                                                       : RunVerdict::Undecided;
    if (v == RunVerdict::AllFail) {
      counters_.rasterized += uint64_t(n);
      counters_.depthFailed += uint64_t(n);
    } else {
      spanBatch(y, yn, start, n, v == RunVerdict::AllPass && earlyDepthTest_);
    }
  }
  // Back off while a triangle's spans' own depths decide nothing: skip those checks for its next
  // 1, 3, 7, 15 spans. Where nothing is decided (a surface crossing the stored depth), a check
  // per span cost dense's wsum accumulation 4–5 %; with the back-off it costs nothing measurable.
  if (checkRuns) {
    rejectBackoff_ = read ? 0 : std::min(kMaxRejectBackoff, 2 * rejectBackoff_ + 1);
    rejectSkip_ = rejectBackoff_;
  }
}

// A run that provably passes (or a draw without a depth test) goes to the shader in batches of
// its columns with NaN depths, counted as rasterized; the runs that provably fail are counted as
// failed; the rest take spanBatch. Batches hold up to kBatch columns of one run, in ascending order.
void FragmentStage::positionSpan(int y, double yn, int x0, int x1) {
  // ALWAYS passes every z: no interval is needed (as without a test).
  const bool testsDepth = depthRunAccepts_ != nullptr && state_.depth.func != CompareFunc::Always;
  if (testsDepth) depthBounds_.beginRow(yn);
  bool read = false;
  for (int start = x0; start < x1; start += kRejectRun) {
    const int n = std::min(kRejectRun, x1 - start);
    double zLow = 0.0, zHigh = 0.0;
    const double first = double(start) * ndcScaleX_ + ndcOffsetX_, last = double(start + n - 1) * ndcScaleX_ + ndcOffsetX_;
    const RunVerdict v = !testsDepth ? RunVerdict::AllPass
                         : depthBounds_.bound(first, last, zLow, zHigh) ? runVerdict(y, start, n, zLow, zHigh, true, read)
                                                                         : RunVerdict::Undecided;
    if (v == RunVerdict::AllPass) {
      if (flatTriangle_ && !flatRowsWritten_) {
        const int attributes = int(attributes_.size());
        for (int k = 0; k < attributes; ++k)
          std::fill_n(batchAttributes_.data() + size_t(k) * kBatch, kBatch, float(vertexAttributes_[size_t(k)]));
        flatRowsWritten_ = true;
      }
      if (planeDepth_ && !windowDepthsFromPlane(yn, start, n)) {  // a depth it cannot prove: the long way
        spanBatch(y, yn, start, n, earlyDepthTest_);
        continue;
      }
      counters_.rasterized += uint64_t(n);
      batchUniform_ = flatTriangle_ ? flatAttributes_ : 0;
      for (int i = 0; i < n; ++i) {
        batchX_[i] = start + i;
        batchZ_[i] = std::numeric_limits<double>::quiet_NaN();
        batchViewDepth_[i] = std::numeric_limits<float>::quiet_NaN();
        if (!planeDepth_) batchDepth_[i] = std::numeric_limits<float>::quiet_NaN();
      }
      shadeAndBlendBatch(y, n, true);
    } else if (v == RunVerdict::AllFail) {
      counters_.rasterized += uint64_t(n);
      counters_.depthFailed += uint64_t(n);
    } else {
      spanBatch(y, yn, start, n, false);
    }
  }
}

// Pixels [start, start + n) of row y (NDC y `yn`), n ≤ kBatch: interpolation, the early depth
// test (unless the run surely `passes` it), the shader and blending.
void FragmentStage::spanBatch(int y, double yn, int start, int n, bool passes) {
  double w[kBatch], b0[kBatch], b1[kBatch], b2[kBatch], z[kBatch];
  // Four lanes at a time over the whole batch (lanes past n compute pixels beyond the span,
  // never used), with explicit vectors: left to itself the compiler used two. interpolate()'s
  // two steps each over the whole batch: each step has one division per lane, and a lane's
  // second division waits for its first; with the steps apart the divisions of different lanes
  // overlap instead of each lane's chain running out before the next begins.
  for (int i = 0; i < n; i += 4) {
    const double x = double(start + i);
    lanes::d4 lw, l0, l1, l2;
    interpolateViewDepth(lanes::d4{x, x + 1.0, x + 2.0, x + 3.0}, yn, l0, l1, l2, lw);
    std::memcpy(w + i, &lw, sizeof lw), std::memcpy(b0 + i, &l0, sizeof l0), std::memcpy(b1 + i, &l1, sizeof l1);
    std::memcpy(b2 + i, &l2, sizeof l2);
  }
  const bool windowDepth = !(passes && skipsWindowDepth_);
  for (int i = 0; i < n; i += 4) {
    lanes::d4 lw, l0, l1, l2, lz = lanes::splat<lanes::d4>(std::numeric_limits<double>::quiet_NaN());
    std::memcpy(&lw, w + i, sizeof lw), std::memcpy(&l0, b0 + i, sizeof l0), std::memcpy(&l1, b1 + i, sizeof l1);
    std::memcpy(&l2, b2 + i, sizeof l2);
    if (windowDepth) interpolateWindowDepth(lw, l0, l1, l2, lz);
    else interpolateBarycentrics(lw, l0, l1, l2);
    std::memcpy(b0 + i, &l0, sizeof l0), std::memcpy(b1 + i, &l1, sizeof l1), std::memcpy(b2 + i, &l2, sizeof l2);
    std::memcpy(z + i, &lz, sizeof lz);
  }
  counters_.rasterized += uint64_t(n);
  // Early depth tests for the whole batch first: where most fragments are hidden, they end here.
  int alive[kBatch];
  int count = n;
  if ((earlyDepthTest_ || earlyReject_) && !passes) {
    count = depthBatchTest_(*fb_.depth, start, y, z, n, alive);
    counters_.depthFailed += uint64_t(n - count);
  } else {
    for (int i = 0; i < n; ++i) alive[i] = i;
  }
  if (discardBatchTest_ && count > 0) count = keepPassingDiscardTest(y, start, n, z, alive, count);
  if (program_->batch) {
    // The survivors as arrays (FragmentBatch), their barycentrics side by side so that each
    // attribute is interpolated over all of them in lanes (interpolateAttribute's expression per
    // lane). Where every fragment survived (the usual case in front of an opaque depth buffer),
    // the span's own arrays are the batch's, converted in lanes.
    if (count == n) {
      for (int j = 0; j < n; j += 4) {
        lanes::d4 lz, lw;
        std::memcpy(&lz, z + j, sizeof lz), std::memcpy(&lw, w + j, sizeof lw);
        const lanes::f4 fz = lanes::convert<lanes::f4>(lz), fw = windowDepth ? lanes::convert<lanes::f4>(lw) : lanes::f4(fz);
        const lanes::i4 x = lanes::i4{0, 1, 2, 3} + (start + j);
        std::memcpy(batchDepth_ + j, &fz, sizeof fz), std::memcpy(batchViewDepth_ + j, &fw, sizeof fw);
        std::memcpy(batchX_ + j, &x, sizeof x);
      }
      std::memcpy(batchZ_, z, sizeof(double) * size_t(n));
      batchUniform_ = interpolateAttributesBatch(b0, b1, b2, count, batchAttributes_.data());
      shadeAndBlendBatch(y, count, true);
      return;
    }
    double c0[kBatch], c1[kBatch], c2[kBatch];
    for (int j = 0; j < count; ++j) {
      const int i = alive[j];
      batchX_[j] = start + i;
      batchZ_[j] = z[i];
      batchDepth_[j] = float(z[i]);
      batchViewDepth_[j] = float(w[i]);
      c0[j] = b0[i], c1[j] = b1[i], c2[j] = b2[i];
    }
    for (int j = count; j % 4; ++j) c0[j] = c1[j] = c2[j] = 0.0;  // the last lanes' inputs: defined
    batchUniform_ = interpolateAttributesBatch(c0, c1, c2, count, batchAttributes_.data());
    shadeAndBlendBatch(y, count, false);
    return;
  }
  int blended = 0;
  for (int j = 0; j < count; ++j) {
    const int i = alive[j];
    FragmentInput in;
    fillInput(in, start + i, y, z[i], w[i]);
    const double b[3] = {b0[i], b1[i], b2[i]};
    if (shade(in, z[i], b, output_, earlyDepthTest_ || earlyReject_)) {
      outputs_.store(blended, output_);
      blendX_[blended] = start + i;
      blendIndex_[blended] = blended;
      ++blended;
    }
  }
  blendBatch(y, blended, blendX_, blendIndex_);
}

int FragmentStage::keepPassingDiscardTest(int y, int start, int n, const double* z, int* alive, int count) {
  // The shader tests gl_FragCoord.z, the window z rounded to fp32 (FragmentInput::depth).
  double fragCoordZ[kBatch];
  for (int i = 0; i < n; ++i) fragCoordZ[i] = double(float(z[i]));
  int passed[kBatch];
  const int passing = discardBatchTest_(*discardBuffer_, start, y, fragCoordZ, n, passed);
  int kept = 0;
  for (int j = 0, p = 0; j < count; ++j) {  // alive ∩ passed, both ascending
    while (p < passing && passed[p] < alive[j]) ++p;
    if (p < passing && passed[p] == alive[j]) alive[kept++] = alive[j];
  }
  counters_.shaded += uint64_t(count - kept);
  counters_.discarded += uint64_t(count - kept);
  return kept;
}

// The depth row of a span two rows ahead, asked for now: a triangle's next spans in the tile
// are there, and the rows of a tile are a page apart, too far for the hardware's
// prefetcher to follow in time (the first load of a span's depths waited on memory). Prefetching
// the colour rows as well measured slower (veils 1080p opaque pass 40 → 44 ms). Only when the
// data arrives changes.
void FragmentStage::prefetchDepthRow(int y, int x0, int x1) const {
  if (!fb_.depth || !state_.depth.testEnabled || y >= height_) return;
  const char* row = static_cast<const char*>(fb_.depth->texel(x0, y));
  const int bytes = (x1 - x0) * fb_.depth->bytesPerTexel();
  for (int b = 0; b < bytes + 63; b += 64) __builtin_prefetch(row + b);
}

void FragmentStage::shadeAndBlendBatch(int y, int count, bool run) {
  if (count == 0) return;  // a batch shader never gets an empty batch
  outputs_.reset(count);
  FragmentBatch batch;
  batch.count = count;
  batch.y = y;
  batch.run = run;
  batch.x = batchX_;
  batch.depth = batchDepth_;
  batch.viewDepth = batchViewDepth_;
  batch.attributes = batchAttributes_.data();
  batch.attributeCount = int(attributes_.size());
  batch.attributeStride = kBatch;
  batch.uniformAttributes = batchUniform_;
  batchUniform_ = 0;
  batch.frontFacing = triangle_ ? triangle_->frontFacing : true;
  batch.primitiveId = triangle_ ? triangle_->primitiveId : 0;
  batch.drawId = drawId_;
  if (derivativesOf_ >= 0 && triangle_) {
    for (int i = 0; i < count; ++i) quadDerivatives(batchX_[i], y, batchDerivatives_ + i, kBatch);
    batch.derivatives = batchDerivatives_;
    batch.derivativeStride = kBatch;
  }
  program_->batch(batch, outputs_);
  counters_.shaded += uint64_t(count);
  int alive = 0;
  if (earlyTests_) {
    // afterShader with the depth test done: discard, and whether a bound output was written.
    // Usually no fragment discarded and all wrote a bound target: then all of them blend.
    if (!boundTargets_) {  // nothing to blend (the A-buffer's passes store through the shader): count the discards
      if (outputs_.anyDiscarded(count))
        for (int i = 0; i < count; ++i) counters_.discarded += outputs_.discarded(i);
      return;
    }
    const unsigned written = outputs_.writtenByAll(count);
    if (!outputs_.anyDiscarded(count) && (written & boundTargets_)) {
      counters_.written += uint64_t(count);
      blendBatch(y, count, batchX_, nullptr, written);
      return;
    }
    uint64_t discarded = 0;
    for (int i = 0; i < count; ++i) {
      discarded += outputs_.discarded(i);
      if (outputs_.discarded(i) || !(outputs_.writtenMask(i) & boundTargets_)) continue;
      blendX_[alive] = batchX_[i];
      blendIndex_[alive++] = i;
    }
    counters_.discarded += discarded;
    counters_.written += uint64_t(alive);
  } else {
    for (int i = 0; i < count; ++i)
      if (afterShader(batchX_[i], y, batchZ_[i], outputs_.discarded(i), outputs_.depthWritten(i), outputs_.depth(i),
                      outputs_.writtenMask(i))) {
        blendX_[alive] = batchX_[i];
        blendIndex_[alive++] = i;
      }
  }
  blendBatch(y, alive, blendX_, blendIndex_);
}

void FragmentStage::fullscreenSpan(int y, int x0, int x1) {
  const bool depthTest = earlyDepthTest_ || earlyReject_;
  if (program_->batch && !depthTest) {
    // Every pixel is a fragment at depth 0 (view depth 1): those lanes once per row, then only
    // the columns per batch.
    const int lanes = std::min(kBatch, x1 - x0);
    for (int i = 0; i < lanes; ++i) batchZ_[i] = 0.0, batchDepth_[i] = 0.0f, batchViewDepth_[i] = 1.0f;
  }
  for (int start = x0; start < x1; start += kBatch) {
    const int n = std::min(kBatch, x1 - start);
    counters_.rasterized += uint64_t(n);
    if (program_->batch && !depthTest) {
      for (int i = 0; i < n; ++i) batchX_[i] = start + i;
      shadeAndBlendBatch(y, n, true);
      continue;
    }
    if (program_->batch) {
      int count = 0;
      for (int i = 0; i < n; ++i) {
        if (depthTest && !earlyTest(start + i, y, 0.0)) continue;
        batchX_[count] = start + i;
        batchZ_[count] = 0.0;
        batchDepth_[count] = 0.0f;
        batchViewDepth_[count++] = 1.0f;
      }
      shadeAndBlendBatch(y, count, count == n);
      continue;
    }
    int alive = 0;
    for (int i = 0; i < n; ++i) {
      FragmentInput in;
      fillInput(in, start + i, y, 0.0, 1.0);
      if (shade(in, 0.0, nullptr, output_)) {
        outputs_.store(alive, output_);
        blendX_[alive] = start + i;
        blendIndex_[alive] = alive;
        ++alive;
      }
    }
    blendBatch(y, alive, blendX_, blendIndex_);
  }
}

void FragmentStage::blendBatch(int y, int count, const int* xs, const int* index, unsigned writtenByAll) {
  const glm::vec4* gathered[kBatch];
  uint8_t* texels[kBatch];
  // The targets every fragment of the batch wrote (the usual case) take all of them without
  // compaction: compacting, each fragment's slot waited on the previous one's written bit.
  // Consecutive pixels (ascending and distinct, so the ends tell): texel addresses by a stride.
  const bool consecutive = count > 0 && xs[count - 1] - xs[0] == count - 1;
  for (unsigned targets = boundTargets_; targets;) {
    const int t = __builtin_ctz(targets);
    targets &= targets - 1;
    Image& image = *fb_.color[size_t(t)];
    uint8_t* row = image.texel(0, y);
    const size_t bytes = image.bytesPerTexel();
    const glm::vec4* colors = outputs_.colors(t);
    int n = 0;
    const glm::vec4* const* sources = gathered;
    if (((writtenByAll >> t) & 1u) && !index && consecutive) {  // a run: the usual case of a span
      blenders_[size_t(t)].blendRun(colors, row + size_t(xs[0]) * bytes, count);
      continue;
    }
    if ((writtenByAll >> t) & 1u) {
      if (index) {
        for (int i = 0; i < count; ++i) gathered[i] = colors + index[i];
      } else {
        sources = allSources_[t];
      }
      if (consecutive) {
        uint8_t* first = row + size_t(xs[0]) * bytes;
        for (int i = 0; i < count; ++i) texels[i] = first + size_t(i) * bytes;
      } else {
        for (int i = 0; i < count; ++i) texels[i] = row + size_t(xs[i]) * bytes;
      }
      n = count;
    } else {
      for (int i = 0; i < count; ++i) {
        const int k = index ? index[i] : i;
        gathered[n] = colors + k;
        texels[n] = row + size_t(xs[i]) * bytes;
        n += (outputs_.writtenMask(k) >> t) & 1u;
      }
    }
    if (n) blenders_[size_t(t)].blendBatch(sources, texels, n);
  }
}

void FragmentStage::fullscreenPixel(int x, int y) {
  FragmentInput in;
  fillInput(in, x, y, 0.0, 1.0);
  ++counters_.rasterized;
  process(in, 0.0, nullptr);
}

void FragmentStage::process(FragmentInput& in, double z, const double* perspectiveBary) {
  if (!shade(in, z, perspectiveBary, output_)) return;
  unsigned targets = output_.writtenMask() & boundTargets_;
  while (targets) {
    const int t = __builtin_ctz(targets);
    targets &= targets - 1;
    blenders_[size_t(t)].blend(output_.color(t), fb_.color[size_t(t)]->texel(in.x, in.y));
  }
}

bool FragmentStage::earlyTest(int x, int y, double z) {
  DepthBuffer* depth = fb_.depth;
  const DepthState& ds = state_.depth;
  if (!(earlyDepthTest_ || earlyReject_)) return true;  // GL §17.3.4: no test, no depth write
  const uint32_t fragmentDepth = encodeDepth(z, depth->format(), depthRounding_);
  if (!depthTestPasses(ds.func, fragmentDepth, depth->load(x, y), depth->format())) {
    ++counters_.depthFailed;
    return false;
  }
  if (earlyDepthTest_ && ds.writeMask) depth->store(x, y, fragmentDepth);
  return true;
}

bool FragmentStage::afterShader(int x, int y, double z, bool discarded, bool depthWritten, float shaderDepth,
                                unsigned written) {
  if (discarded) {
    ++counters_.discarded;
    return false;
  }
  DepthBuffer* depth = fb_.depth;
  const DepthState& ds = state_.depth;
  if (!earlyTests_ && depth != nullptr && ds.testEnabled) {
    const uint32_t fragmentDepth = encodeDepth(depthWritten ? double(shaderDepth) : z, depth->format(), depthRounding_);
    if (!depthTestPasses(ds.func, fragmentDepth, depth->load(x, y), depth->format())) {
      ++counters_.depthFailed;
      return false;
    }
    if (ds.writeMask) depth->store(x, y, fragmentDepth);
  }
  if (!(written & boundTargets_)) return false;
  ++counters_.written;
  return true;
}

// Attributes are interpolated only for fragments that reach the shader.
bool FragmentStage::shade(FragmentInput& in, double z, const double* perspectiveBary, FragmentOutput& out,
                          bool earlyTestDone) {
  if (!earlyTestDone && !earlyTest(in.x, in.y, z)) return false;
  if (perspectiveBary) interpolateAttributes(perspectiveBary, attributes_.data());
  if (derivativesOf_ >= 0 && triangle_) {
    quadDerivatives(in.x, in.y, derivatives_, 1);
    in.derivatives = derivatives_;
    in.derivativeStride = 1;
  }
  out.reset();
  program_->shader(in, out);
  ++counters_.shaded;
  return afterShader(in.x, in.y, z, out);
}

}  // namespace oitref::detail
