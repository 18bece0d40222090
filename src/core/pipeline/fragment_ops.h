// Stage 5: per-fragment operations, in the order of GL 4.6 chapters 14.9, 15 and 17:
// attribute interpolation → (early) depth test → fragment shader → (late) depth test →
// depth write → blending and colour write for each output the shader wrote.
//
// Interpolation (GL 4.6 §14.6.1 eq. 14.9, 14.10) is exact for the original triangle, in double,
// at the pixel centre: snapping and clipping decide coverage only. With M the 3×3 matrix whose
// columns are the original vertices' clip (x, y, w) and (x_n, y_n) the pixel centre in NDC,
//   k = M⁻¹ · (x_n, y_n, 1),  b = k / Σk        perspective-correct barycentrics
//   P = Σ b_i V_i                                the surface point in clip space
//   view depth = P.w,  window z = ½·P.z/P.w + ½  (linear in window space, eq. 14.10)
//   a = Σ b_i a_i                                each attribute, then rounded once to fp32
// (homogeneous rasterization, Olano & Greer 1997). A triangle whose plane contains the eye
// (det M = 0) is seen edge-on and produces no fragments.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "blend/target_blender.h"
#include "oitref/core/lanes.h"
#include "oitref/core/renderer.h"
#include "pipeline/depth_batch.h"
#include "pipeline/depth_bounds.h"
#include "pipeline/setup.h"

namespace oitref::detail {

struct FragmentCounters {
  uint64_t rasterized = 0, shaded = 0, depthFailed = 0, discarded = 0, written = 0;
};

class FragmentStage {
 public:
  // `viewport` maps pixel centres to NDC: x_n = 2(x + ½ − vx)/vw − 1, likewise y.
  FragmentStage(Framebuffer& fb, const PipelineState& state, const FragmentProgram& program, const Geometry* geometry,
                const PixelRect& viewport, uint32_t drawId = 0);
  FragmentStage(const FragmentStage&) = delete;  // allSources_ points into the stage itself
  FragmentStage& operator=(const FragmentStage&) = delete;

  // The next draw of a sequence with the same framebuffer and state (Renderer::drawSequence):
  // its program, geometry and id; the blenders and counters carry over.
  void beginDraw(const FragmentProgram& program, const Geometry* geometry, uint32_t drawId);
  // The tile whose pixels this stage draws (Renderer::drawSequence), before its first span: the
  // extent of its rows' stored depth ranges (rowDepthRange).
  void beginTile(const PixelRect& tile);
  // Takes the triangle's interpolation set-up (M⁻¹, clip z: setup.h) and its vertices' attributes
  // before its fragments arrive; under raster=llvmpipe, its plane equations (`planes`,
  // llvmpipe_setup.h) instead.
  void beginTriangle(const SetupTriangle& triangle, const float* planes = nullptr);
  // Asks for the memory that beginTriangle(triangle) will read (a hint; nothing changes).
  void prefetchVertices(const SetupTriangle& triangle) const {
    if (geometry_->attributeCount)
      for (uint32_t v : triangle.vertexIndex) __builtin_prefetch(geometry_->vertexAttributes(v));
  }
  // A covered pixel centre of the current triangle.
  void fragment(int x, int y);
  // A full-screen pass pixel: window depth 0, no attributes.
  void fullscreenPixel(int x, int y);
  // The covered pixel centres [x0, x1) of row y of the current triangle (span), or of a full-screen
  // pass (fullscreenSpan): the operations of fragment() and fullscreenPixel() for each, with the
  // blending batched per target. The pixels of a span are distinct, so running every fragment's
  // tests and shader before any blend changes nothing a fragment can see of its own pixel.
  // A span's runs that the early depth test surely rejects are counted as failed without being
  // interpolated (depth_bounds.h), as the per-fragment test would have failed each of them.
  void span(int y, int x0, int x1);
  void fullscreenSpan(int y, int x0, int x1);

  const FragmentCounters& counters() const { return counters_; }

  // The bound on B = |b0| + |b1| + |b2| below which an attribute equal at the three vertices
  // interpolates to that value (flatAttributeValue).
  static constexpr double kFlatBarycentricBound = 1048576.0;  // 2^20
  // Whether every pixel centre of `r` has B < kFlatBarycentricBound, B as interpolate() computes
  // it there for the triangle `t` with the NDC map x_n = x·ndc[0] + ndc[1], y_n = y·ndc[2] +
  // ndc[3] (a proof over the rectangle's corners, at the definition). False where it cannot tell.
  // `bound`, where given and the answer is yes: ΣT_i and bounds on each |k̂_i| over the rectangle
  // (the proof's T and max|k̃_i| + 12u·T), for the window depth's plane (beginTriangle).
  struct RectangleBound {
    double T = 0.0, K[3] = {0.0, 0.0, 0.0};
  };
  static bool barycentricsBoundedOn(const TriangleInterpolation& t, const double (&ndc)[4], const PixelRect& r,
                                    RectangleBound* bound = nullptr);
  // z_w = ½·(a·x_n + b·y_n + c) + ½, evaluated in double with at most three roundings for the
  // parenthesis, lies within `error` of interpolate()'s window z at every pixel centre of a
  // rectangle whose RectangleBound is `bound` (the proof is at the definition). False where the
  // margin would be too wide to use (2^−30 or more).
  struct WindowDepthPlane {
    double a = 0.0, b = 0.0, c = 0.0, error = 0.0;
  };
  static bool windowDepthPlane(const TriangleInterpolation& t, const RectangleBound& bound, WindowDepthPlane& plane);
  // k_i = M⁻¹_i·(x_n, y_n, 1) for row i of M⁻¹, at one pixel or in lanes: interpolate()'s first
  // products and sums, in its order.
  template <typename D>
  static D inverseRowAt(const double (&row)[3], D xn, double yn) {
    return row[0] * xn + row[1] * yn + row[2];
  }

 private:
  void process(FragmentInput& in, double z, const double* perspectiveBary);
  // Everything before blending; true when the fragment reaches blending with `out`'s colours.
  // `earlyTestDone`: the caller ran the early depth test (and write) already.
  bool shade(FragmentInput& in, double z, const double* perspectiveBary, FragmentOutput& out, bool earlyTestDone = false);
  // The early depth test and write, where the program has early tests (the test alone, for
  // earlyReject_); false when it fails.
  bool earlyTest(int x, int y, double z);
  // After the shader: discard, the late depth test and write (window z `z` unless the shader set
  // one), and whether the fragment wrote a bound output, which makes it reach blending.
  bool afterShader(int x, int y, double z, bool discarded, bool depthWritten, float shaderDepth, unsigned written);
  bool afterShader(int x, int y, double z, const FragmentOutput& out) {
    return afterShader(x, y, z, out.discarded(), out.depthWritten(), out.depth(), out.writtenMask());
  }
  // The batch path: the fragments [0, count) of row y in the batch arrays (batchX_, batchZ_, …),
  // early-tested already, shaded by one program_->batch call, then afterShader and blending.
  // `run`: the columns are batchX_[0] + i (FragmentBatch::run).
  void shadeAndBlendBatch(int y, int count, bool run);
  // raster=llvmpipe (fragment_llvmpipe.cpp): the pixels [start, start + n) of row y, n ≤ kBatch,
  // with depth, 1/w and attributes from the triangle's fp32 planes as llvmpipe's fragment shader
  // computes them (llvmpipe_setup.h), then the early depth test, the shader and blending.
  void llvmpipeBatch(int y, int start, int n);
  // The attributes [k, k + 2) at pixel (x, y) of the current triangle under raster=llvmpipe.
  void llvmpipeAttributesAt(int x, int y, int k, float out[2]) const;
  // span() for a draw whose program reads neither depths nor attributes (positionOnly_), or only
  // attributes that are the same at every pixel of the triangle in the tile (flatTriangle_): runs
  // that provably pass the depth test go to the shader as they are, without interpolation.
  void positionSpan(int y, double yn, int x0, int x1);
  // The pixels [start, start + n) of row y at NDC y `yn`, n ≤ kBatch, through the batch path:
  // interpolation in lanes, the early depth test, then shadeAndBlendBatch (or the per-fragment
  // shader and blendBatch). `passes`: the run surely passes the early depth test (span(): its
  // window-z interval against depthRunAccepts_), which is then not run fragment by fragment.
  void spanBatch(int y, double yn, int start, int n, bool passes);
  // What the depth test gives every pixel of the run [start, start + n) of row y, whose window z
  // lies in [zLow, zHigh]: the stored range of the tile's row (rowDepthRange) decides first, then,
  // where `checkRuns`, the run's own stored depths (depthRunRejects_, depthRunAccepts_; `read`
  // set when they decided).
  RunVerdict runVerdict(int y, int start, int n, double zLow, double zHigh, bool checkRuns, bool& read);
  // The stored depths of row y across the tile, summarised the first time a span of the row asks.
  const StoredDepthRange& rowDepthRange(int y);
  DepthRangeVerdict drawRangeVerdict() const;
  // Of the fragments alive[0, count) of the span's pixels [start, start + n) with window z `z`,
  // keeps those that pass the program's discardTest (in place, ascending) and returns how many;
  // the others count as shaded and discarded.
  int keepPassingDiscardTest(int y, int start, int n, const double* z, int* alive, int count);
  // a = Σ b_i a_i, rounded once to fp32 (the header comment), for one fragment's attributes, or
  // for `count` fragments' as rows (attribute k of fragment j at out[k·kBatch + j]), four lanes
  // at a time.
  static float interpolateAttribute(double b0, double b1, double b2, double a0, double a1, double a2) {
    return float(b0 * a0 + b1 * a1 + b2 * a2);
  }
  void interpolateAttributes(const double* b, float* out) const;
  // An attribute whose three vertices hold the same float a, finite and not zero, interpolates to
  // a itself at every pixel where B = |b0| + |b1| + |b2| < 2^20. Proof, with u = 2^−53: the lane's
  // r = (b0·a + b1·a) + b2·a in double is within γ3·B·|a| of (b0 + b1 + b2)·a (three roundings
  // at most per term; a product that underflows adds 2^−1075, far below a float's spacing), and
  // b_i = k_i·w, w = 1/((k0 + k1) + k2) put b0 + b1 + b2 within u + (γ2 + u)·B·(1 + 3u) of 1
  // (Σ|k_i|·|w| ≤ B/(1 − u)). So |r − a| ≤ 7u·B·|a| < 2^−30·|a| (B ≥ 1 since Σ b_i ≈ 1); every
  // float a is at least 2^−25·|a| from the nearest rounding boundary of fp32 (half the spacing
  // below a power of two; subnormals are farther), so fp32(r) = a. Zero is left out because the
  // sign of r's zero depends on the b_i's signs, and NaN and infinities because b_i·a can be NaN.
  static bool flatAttributeValue(double a0, double a1, double a2) {
    return a0 == a1 && a1 == a2 && a0 != 0.0 && std::isfinite(a0);
  }
  // Returns the attributes it wrote as their vertices' common value (bit k), for FragmentBatch::
  // uniformAttributes.
  uint64_t interpolateAttributesBatch(const double* b0, const double* b1, const double* b2, int count, float* out) const;
  void fillInput(FragmentInput& in, int x, int y, double z, double w) const;
  // Pixel x of the row at NDC y `yn`: the perspective-correct barycentrics b, the view depth w and
  // the window z, the expressions of the header comment, one rounding each in double. On one
  // pixel (D = double, x an int) or four of a span (D = lanes::d4, x their columns as doubles,
  // exact): the same IEEE operations in every lane.
  template <typename D, typename X>
  void interpolate(X x, double yn, D& w, D& b0, D& b1, D& b2, D& z) const {
    interpolateViewDepth(x, yn, b0, b1, b2, w);
    interpolateWindowDepth(w, b0, b1, b2, z);
  }
  // interpolate() in two steps. The first: k = M⁻¹·(x_n, y_n, 1) (left in b0, b1, b2) and P.w.
  template <typename D, typename X>
  void interpolateViewDepth(X x, double yn, D& k0, D& k1, D& k2, D& w) const {
    const double(&inverse)[3][3] = interpolation_->inverse;
    const D xn = D(x) * ndcScaleX_ + ndcOffsetX_;
    k0 = inverseRowAt(inverse[0], xn, yn);
    k1 = inverseRowAt(inverse[1], xn, yn);
    k2 = inverseRowAt(inverse[2], xn, yn);
    w = 1.0 / (k0 + k1 + k2);  // P.w, the view depth
  }
  // The second: b = k·w in place, and the window z.
  template <typename D>
  void interpolateWindowDepth(D w, D& b0, D& b1, D& b2, D& z) const {
    const double* clipZ = interpolation_->clipZ;
    interpolateBarycentrics(w, b0, b1, b2);
    z = 0.5 * ((b0 * clipZ[0] + b1 * clipZ[1] + b2 * clipZ[2]) / w) + 0.5;
  }
  // Its first half alone, b = k·w, where no one needs the window z (skipsWindowDepth_).
  template <typename D>
  void interpolateBarycentrics(D w, D& b0, D& b1, D& b2) const {
    b0 = b0 * w, b1 = b1 * w, b2 = b2 * w;
  }
  // Blends `count` fragments of the batch target by target: outputs_'s fragment index[i] (i when
  // index is null: all of them) at x = xs[i] on row y.
  // `writtenByAll`: the targets every one of those fragments wrote, where the caller knows them.
  void blendBatch(int y, int count, const int* xs, const int* index) {
    blendBatch(y, count, xs, index, writtenByAll(count, index));
  }
  void blendBatch(int y, int count, const int* xs, const int* index, unsigned writtenByAll);
  // The targets that outputs_'s fragments index[i], i < count (i when index is null), all wrote.
  unsigned writtenByAll(int count, const int* index) const {
    if (!index) return outputs_.writtenByAll(count);
    unsigned all = ~0u;
    for (int i = 0; i < count; ++i) all &= outputs_.writtenMask(index[i]);
    return all;
  }
  // The derivatives of attributes derivativesOf_, derivativesOf_ + 1 for the fragment at (x, y)
  // of the current triangle (FragmentInput::derivatives), at out[i · stride]: GL 4.6 §15.2.3's
  // fine differences over its 2×2 quad, ∂/∂x between the quad's two pixels of row y, ∂/∂y
  // between its two of column x. Each of those pixels, covered or not (a helper invocation), has
  // the attributes this stage's interpolation gives there, rounded to fp32 as an invocation holds
  // them; the differences are taken in double.
  void quadDerivatives(int x, int y, double* out, int stride) const;
  void prefetchDepthRow(int y, int x0, int x1) const;

  static constexpr int kBatch = FragmentBatch::kCapacity;
  // The pixels span() asks depthRunRejects_ about at a time: a whole span in the default tiles,
  // 128 pixels wide (Renderer::tileShapeFor). Shorter runs reject more of a span whose depth
  // crosses the stored one, but a rejected run splits the batch around it, and each batch has a
  // cost of its own (dense's opaque frame: 81–106 ms with runs of 16, 63–66 with one run per span).
  static constexpr int kRejectRun = kBatch;  // span() takes each run as one batch

  Framebuffer& fb_;
  const PipelineState& state_;
  const FragmentProgram* program_;
  const Geometry* geometry_;
  const SetupTriangle* triangle_ = nullptr;
  uint32_t drawId_ = 0;
  const TriangleInterpolation* interpolation_ = nullptr;  // of the current triangle (setup.h)
  // raster=llvmpipe: the current triangle's planes (llvmpipe_setup.h), fused multiply-adds, and
  // d16/d24 depth from the fp32 product; every fragment then takes llvmpipeBatch.
  bool llvmpipe_ = false, fused_ = false;
  const float* planes_ = nullptr;
  UnormRounding depthRounding_ = UnormRounding::ExactNearestEven;
  double ndcScaleX_, ndcOffsetX_, ndcScaleY_, ndcOffsetY_;
  int height_;  // the framebuffer's
  bool earlyTests_;
  bool earlyDepthTest_;  // early tests, and a depth test to run
  // A pure program tested late (it may discard): the test also runs before the shader, without
  // writing, and a fragment that fails it is not shaded (FragmentProgram::pure).
  bool earlyReject_;
  DepthBatchTest depthBatchTest_ = nullptr;  // span's early test, for the draw's depth state
  // The program's own depth test (FragmentProgram::discardTest), applied before shading where the
  // program is pure: the test without writing, and its buffer; null where there is none.
  DepthBatchTest discardBatchTest_ = nullptr;
  DepthBuffer* discardBuffer_ = nullptr;
  // Rejecting runs whose window-z interval fails the test (depth_bounds.h): null where the draw
  // tests no depth early or its compare function has no such bound.
  DepthRunRejects depthRunRejects_ = nullptr;
  WindowDepthBounds depthBounds_;  // of the current triangle and span
  // A batch program that reads no depth and no attribute, tested early without depth writes
  // (FragmentProgram::readsDepth): span() takes positionSpan(). depthRunAccepts_: the draw's
  // test of a run that surely passes, null where it tests no depth.
  bool positionOnly_ = false;
  // A draw whose program could take positionSpan() but reads attributes (positionOnly_'s other
  // conditions), and, per triangle, one whose attributes are all flat (flatAttributes_) with B
  // bounded over its pixels in the tile (barycentricsBoundedOn): its batches' attribute rows are
  // the vertices' values, written once per triangle (flatRowsWritten_; where spanBatch takes one
  // of its runs, it writes the same values, by the proof).
  bool flatEligible_ = false, flatTriangle_ = false, flatRowsWritten_ = false;
  // The current triangle has flat attributes (all, or some) and its B is bounded over its pixels
  // in the tile, whatever the program (flatTriangle_ needs all flat and an eligible program as
  // well): interpolation writes the flat ones without checking each batch's lanes.
  bool flatProven_ = false;
  // A draw whose program reads the window depth but not the view depth (FragmentProgram::
  // readsViewDepth), with flatEligible_'s other conditions; per triangle, one of them with all
  // attributes flat, flatProven_, with a usable depth plane (depthPlane_): positionSpan() gives
  // its runs that surely pass the depth test fp32 window depths from the plane, proven to be
  // interpolate()'s rounded (windowDepthsFromPlane), and NaN view depths.
  bool planeDepthEligible_ = false, planeDepth_ = false;
  WindowDepthPlane depthPlane_;  // of the current triangle, where planeDepth_
  bool windowDepthsFromPlane(double yn, int start, int n);
  uint64_t batchUniform_ = 0;  // FragmentBatch::uniformAttributes of the next shadeAndBlendBatch
  // A batch program that reads no depth (FragmentProgram::readsDepth), with early tests and no
  // discard test of its own: a run that surely passes the depth test needs no window z, and its
  // fragments reach the shader with NaN depths.
  bool skipsWindowDepth_ = false;
  DepthRunAccepts depthRunAccepts_ = nullptr;
  // Where the draw tests depth without writing it, the stored depths of the tile do not change
  // during the draw sequence: each row's range (least and greatest) is read once and decides
  // whole runs against their window-z interval without reading their depths again (a GPU's
  // hierarchical depth test). Null otherwise, and for stages without a tile.
  DepthRangeVerdict rangeVerdict_ = nullptr;
  PixelRect tile_{0, 0, 0, 0};
  static constexpr int kMaxTileRows = 256;  // Renderer's largest tile size
  StoredDepthRange rowRanges_[kMaxTileRows];
  uint64_t rowRangesKnown_[kMaxTileRows / 64] = {};
  static constexpr int kMaxRejectBackoff = 15;
  int rejectBackoff_ = 0, rejectSkip_ = 0;  // spans of the current triangle to take without the check
  unsigned boundTargets_ = 0;
  std::vector<TargetBlender> blenders_;  // per bound target, in target order
  std::vector<double> vertexAttributes_;  // 3 × attributeCount, of the original vertices
  // The current triangle's attributes (the first 64) that interpolate to their vertices' common
  // value wherever the batch's barycentrics are bounded (flatAttributeValue): bit k for attribute k.
  uint64_t flatAttributes_ = 0;
  std::vector<float> attributes_;         // interpolated, for the shader
  FragmentOutput output_;
  FragmentCounters counters_;
  FragmentBatchOutput outputs_;  // a batch's, for span() and fullscreenSpan()
  // Per target, the sources of a batch that blends all of its fragments in order: fragment i's
  // colour, outputs_.colors(t) + i (fixed for the stage's life: it is not copied or moved).
  const glm::vec4* allSources_[kMaxColorTargets][kBatch];
  int blendX_[kBatch], blendIndex_[kBatch];
  // The batch path's fragments as arrays (FragmentBatch): columns, window depth in double (the
  // depth test's) and in fp32 (gl_FragCoord.z), view depth, and the attributes' rows.
  int batchX_[kBatch];
  double batchZ_[kBatch];
  float batchDepth_[kBatch], batchViewDepth_[kBatch];
  std::vector<float> batchAttributes_;    // attributeCount rows of kBatch
  // FragmentProgram::derivativesOf of the draw, and the derivatives of one fragment (the
  // per-fragment path) or of a batch (four rows of kBatch).
  int derivativesOf_ = -1;
  double derivatives_[4];
  double batchDerivatives_[4 * kBatch];
};

}  // namespace oitref::detail
