// Fragment shaders are C++ callables. A shader reads FragmentInput and writes FragmentOutput:
// any subset of the bound colour outputs, optionally the depth, or it discards.
//
// To read an earlier pass's attachment at the fragment's own pixel (texelFetch), capture the
// Image and call image.fetch(in.x, in.y). Reading an attachment that the same pass writes is a
// feedback loop (undefined in GL); oitref returns the value before this fragment's own write.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "oitref/core/image.h"
#include "oitref/core/pipeline_state.h"

namespace oitref {

struct FragmentInput {
  int x = 0, y = 0;          // pixel, window coordinates (origin lower-left)
  glm::vec2 fragCoord{};     // gl_FragCoord.xy = (x + ½, y + ½)
  float depth = 0;           // gl_FragCoord.z: window z, linear in window space
  float viewDepth = 0;       // clip w interpolated perspective-correctly (= −z_eye for a perspective camera)
  bool frontFacing = true;   // gl_FrontFacing
  uint32_t primitiveId = 0;  // gl_PrimitiveID: the triangle's index in its draw
  uint32_t drawId = 0;       // the draw's Renderer::DrawCall::drawId (0 for draw() and full-screen passes)
  // The perspective-correct interpolated attributes: attribute i at attributes[i · attributeStride]
  // (1 for one fragment; a batch's row length where the attributes are rows: FragmentBatch).
  const float* attributes = nullptr;
  int attributeCount = 0;
  int attributeStride = 1;
  // Where the program asks for them (FragmentProgram::derivativesOf = k): the derivatives of
  // attributes k and k + 1 (texture coordinates s, t) over the fragment's 2×2 quad, at
  // derivatives[i · derivativeStride] for i = 0 ∂s/∂x, 1 ∂t/∂x, 2 ∂s/∂y, 3 ∂t/∂y; null otherwise
  // (and in full-screen passes).
  const double* derivatives = nullptr;
  int derivativeStride = 1;

  float attribute(int i) const { return attributes[i * attributeStride]; }
  glm::vec2 vec2At(int i) const { return {attribute(i), attribute(i + 1)}; }
  glm::vec3 vec3At(int i) const { return {attribute(i), attribute(i + 1), attribute(i + 2)}; }
  glm::vec4 vec4At(int i) const { return {attribute(i), attribute(i + 1), attribute(i + 2), attribute(i + 3)}; }
};

// Fragments of distinct pixels of one row and one primitive, as arrays (a structure of arrays):
// fragment i is at (x[i], y), with window depth depth[i] and view depth viewDepth[i], and its
// attribute k at attributes[k · attributeStride + i], so that a batch shader's loop over the
// fragments reads each input as one contiguous row. What is the same for all (the row, the
// primitive, the draw) is stored once. in[i] is fragment i as one FragmentInput.
struct FragmentBatch {
  // The most fragments the rasterizer puts into one batch: a span of one row in a tile of the
  // default shape (Renderer::tileShapeFor). Each batch costs a part of its own (the calls, the
  // shader's and the blend's set-up, their last partial groups of lanes): with 128 in tiles of
  // 128×32, dense's WBOIT accumulation took 15–18 % less time than with 64 in tiles of 64×64;
  // 256 in tiles of 256×16 gained 1–2 % more.
  static constexpr int kCapacity = 128;
  int count = 0;
  int y = 0;
  const int* x = nullptr;
  const float* depth = nullptr;
  const float* viewDepth = nullptr;
  const float* attributes = nullptr;
  int attributeCount = 0;
  int attributeStride = 0;
  const double* derivatives = nullptr;  // fragment i's at derivatives[c · derivativeStride + i]
  int derivativeStride = 0;
  // Bit k (k < 64): attribute k holds one value in every fragment of the batch (the rasterizer's
  // flat attributes), so a shader may read it once. A hint: 0 promises nothing.
  uint64_t uniformAttributes = 0;
  // x[i] = x[0] + i for every fragment: a run of the row's pixels (a full-screen pass's batches,
  // and a span's where every fragment survived). A hint: false promises nothing.
  bool run = false;
  bool frontFacing = true;
  uint32_t primitiveId = 0;
  uint32_t drawId = 0;

  FragmentInput operator[](int i) const {
    FragmentInput in;
    in.x = x[i];
    in.y = y;
    in.fragCoord = {float(x[i]) + 0.5f, float(y) + 0.5f};
    in.depth = depth[i];
    in.viewDepth = viewDepth[i];
    in.frontFacing = frontFacing;
    in.primitiveId = primitiveId;
    in.drawId = drawId;
    in.attributes = attributes ? attributes + i : nullptr;  // none: full-screen passes, attribute-less draws
    in.attributeCount = attributeCount;
    in.attributeStride = attributeStride;
    in.derivatives = derivatives ? derivatives + i : nullptr;
    in.derivativeStride = derivativeStride;
    return in;
  }
  // The batch of the one fragment `in` (its fields point into `in`).
  static FragmentBatch of(const FragmentInput& in) {
    FragmentBatch b;
    b.count = 1;
    b.run = true;
    b.y = in.y;
    b.x = &in.x;
    b.depth = &in.depth;
    b.viewDepth = &in.viewDepth;
    b.attributes = in.attributes;
    b.attributeCount = in.attributeCount;
    b.attributeStride = in.attributeStride;
    b.derivatives = in.derivatives;
    b.derivativeStride = in.derivativeStride;
    b.frontFacing = in.frontFacing;
    b.primitiveId = in.primitiveId;
    b.drawId = in.drawId;
    return b;
  }
};

class FragmentOutput {
 public:
  FragmentOutput() : color_{} {}
  // Not copied: a FragmentBatchOutput's view points into the batch's arrays.
  FragmentOutput(const FragmentOutput&) = delete;
  FragmentOutput& operator=(const FragmentOutput&) = delete;

  void write(int target, const glm::vec4& color) {
    colors_[target * stride_] = color;
    written_ |= 1u << target;
  }
  void discard() { discarded_ = true; }
  void setDepth(float windowZ) {  // gl_FragDepth; the program must declare writesDepth
    depth_ = windowZ;
    depthWritten_ = true;
  }

  const glm::vec4& color(int target) const { return colors_[target * stride_]; }
  unsigned writtenMask() const { return written_; }
  bool discarded() const { return discarded_; }
  bool depthWritten() const { return depthWritten_; }
  float depth() const { return depth_; }
  void reset() {
    written_ = 0;
    discarded_ = false;
    depthWritten_ = false;
  }

 private:
  friend class FragmentBatchOutput;
  // A view whose colours are written straight into a batch's arrays (colors[t · stride]): no copy
  // between the shader's writes and blending, whose 16-byte loads of colours written a channel
  // at a time would wait (no store forwarding).
  FragmentOutput(glm::vec4* colors, int stride) : colors_(colors), stride_(stride) {}

  std::array<glm::vec4, kMaxColorTargets> color_;  // a fragment's own (zero until written)
  glm::vec4* colors_ = color_.data();
  int stride_ = 1;
  unsigned written_ = 0;
  bool discarded_ = false;
  bool depthWritten_ = false;
  float depth_ = 0;
};

using FragmentShader = std::function<void(const FragmentInput&, FragmentOutput&)>;

// What FragmentOutput holds, for the fragments of a FragmentBatch, as arrays: target t's colour
// of fragment i at color(t, i), so that blending reads a target's colours as one array.
class FragmentBatchOutput {
 public:
  static constexpr int kCapacity = FragmentBatch::kCapacity;
  void write(int i, int target, const glm::vec4& color) {
    color_[target][i] = color;
    state_[i] = uint16_t(state_[i] | 1u << target);
  }
  // write(i, target, color) where `written`, else nothing, without a branch (the colour's slot
  // is filled either way; an unwritten slot is never read).
  void writeIf(int i, int target, const glm::vec4& color, bool written) {
    color_[target][i] = color;
    state_[i] = uint16_t(state_[i] | unsigned(written) << target);
  }
  // A shader that writes the same targets for every fragment of a batch: each colour by
  // writeColor, then markWritten once for all of them. The same outputs as write() for each; the
  // states' or runs in vector lanes instead of one load and store per fragment and target.
  void writeColor(int i, int target, const glm::vec4& color) { color_[target][i] = color; }
  // Target t's colours as one array (fragment i's at [i]), for such a shader that writes several
  // fragments' colours at once (vector lanes); then markWritten as after writeColor.
  glm::vec4* colorRow(int target) { return color_[target]; }
  void markWritten(int count, unsigned targets) {
    for (int i = 0; i < count; ++i) state_[i] = uint16_t(state_[i] | (targets & kWrittenMask));
  }
  void discard(int i) { state_[i] = uint16_t(state_[i] | kDiscarded); }
  void setDepth(int i, float windowZ) {
    depth_[i] = windowZ;
    state_[i] = uint16_t(state_[i] | kDepthWritten);
  }
  // Fragment i's outputs as a FragmentOutput that writes its colours here; finish(i, view) takes
  // the rest of what the shader left in it.
  FragmentOutput view(int i) { return FragmentOutput(&color_[0][i], kCapacity); }
  void finish(int i, const FragmentOutput& view) {
    state_[i] = uint16_t(view.writtenMask() | (view.discarded() ? kDiscarded : 0u) |
                         (view.depthWritten() ? kDepthWritten : 0u));
    if (view.depthWritten()) depth_[i] = view.depth();
  }
  // Fragment i's outputs as a per-fragment shader left them in `out`, and back.
  void store(int i, const FragmentOutput& out) {
    finish(i, out);
    for (unsigned t = out.writtenMask(); t; t &= t - 1) color_[__builtin_ctz(t)][i] = out.color(__builtin_ctz(t));
  }
  void load(int i, FragmentOutput& out) const {
    for (unsigned t = writtenMask(i); t; t &= t - 1) out.write(__builtin_ctz(t), color_[__builtin_ctz(t)][i]);
    if (discarded(i)) out.discard();
    if (depthWritten(i)) out.setDepth(depth_[i]);
  }

  const glm::vec4& color(int target, int i) const { return color_[target][i]; }
  const glm::vec4* colors(int target) const { return color_[target]; }
  unsigned writtenMask(int i) const { return state_[i] & kWrittenMask; }
  bool discarded(int i) const { return state_[i] & kDiscarded; }
  bool depthWritten(int i) const { return state_[i] & kDepthWritten; }
  float depth(int i) const { return depth_[i]; }
  // Of fragments [0, count): the targets every one wrote, and whether any was discarded. One
  // pass over the states as and/or reductions, which run in vector lanes (a loop over
  // writtenMask(i) and discarded(i) carried its result from fragment to fragment).
  unsigned writtenByAll(int count) const {
    unsigned all = kWrittenMask;
    for (int i = 0; i < count; ++i) all &= state_[i];
    return all;
  }
  bool anyDiscarded(int count) const {
    unsigned any = 0;
    for (int i = 0; i < count; ++i) any |= state_[i];
    return any & kDiscarded;
  }
  // Nothing written, discarded or depth set for fragments [0, count).
  void reset(int count) {
    for (int i = 0; i < count; ++i) state_[i] = 0;
  }

 private:
  static_assert(kMaxColorTargets <= 8, "state_ holds the written targets in its low 8 bits");
  static constexpr unsigned kWrittenMask = 0xffu, kDiscarded = 1u << 8, kDepthWritten = 1u << 9;
  glm::vec4 color_[kMaxColorTargets][kCapacity];
  uint16_t state_[kCapacity];  // per fragment: the written targets, discarded, depth written
  float depth_[kCapacity];
};

// The same shader over a batch: out's fragment i for in[i], i < in.count (1 ≤ in.count ≤
// FragmentBatch::kCapacity), out reset for them beforehand.
// Optional, for speed (one call per batch, the per-fragment code inlined into the loop); it must
// compute exactly what `shader` computes for each fragment, which stays the oracle
// (RendererOptions::perFragment). programOf() below makes both from one callable.
using FragmentBatchShader = std::function<void(const FragmentBatch& in, FragmentBatchOutput& out)>;

// A shader plus what it declares, which decides early or late depth testing (GL 4.6 §14.9.4,
// §15.2.4): a shader that neither discards nor writes depth is tested before shading; one that
// may discard or writes depth is tested after; earlyFragmentTests (GLSL
// layout(early_fragment_tests)) forces the test and the depth write before shading even then.
// Outputs the shader does not write leave their attachment unchanged for that fragment.
// A shader that declares writesDepth but does not call setDepth keeps the interpolated depth.
//
// `pure`: the shader's only effects are its outputs and discard (no image stores, atomics or
// counters). Then a fragment that fails the depth test is not shaded even where the test comes
// after the shader (a shader that may discard): its shading could change nothing, because the
// shader cannot move the fragment's depth or the buffer's. The depth write still waits for the
// shader, so the stored bits are those of the late test; only the counters tell (such fragments
// count as failing the depth test, not as shaded or discarded). GPUs reject early the same way.
// A depth test that a shader applies itself (depth peeling's test against the previous layer):
// it discards exactly the fragments for which depthTestPasses(func, encodeDepth(gl_FragCoord.z,
// buffer's format), the depth stored in `buffer` at the fragment's pixel, buffer's format) fails,
// and for them does nothing else. None where buffer is null. `read`: how the shader reads the
// stored depth back (depthCodeAsFetched; exact: the stored value).
struct ShaderDepthTest {
  const DepthBuffer* buffer = nullptr;
  CompareFunc func = CompareFunc::Always;
  TextureFiltering read = TextureFiltering::Exact;
};

struct FragmentProgram {
  FragmentShader shader;
  bool mayDiscard = false;
  bool writesDepth = false;
  bool earlyFragmentTests = false;
  FragmentBatchShader batch = {};  // optional: `shader` over a batch
  bool pure = false;
  // How many of the geometry's attributes, from the first, the shader reads (−1: all): only those
  // are interpolated, and FragmentInput::attributeCount says so (GL interpolates only the
  // inputs a shader uses, too).
  int attributesRead = -1;
  // The shader's own depth test, declared (ShaderDepthTest). With `pure`, the pipeline may discard
  // the fragments that fail it without shading them, counting them as shaded and discarded, as if
  // the shader had run (its bits are the same either way): peeling's later passes discard most of
  // their fragments so. The shader must still apply the test itself: it is the oracle.
  ShaderDepthTest discardTest = {};
  // The first of two attributes (texture coordinates s, t) whose derivatives over the fragment's
  // 2×2 quad the shader reads (FragmentInput::derivatives; implicit level of detail, GL 4.6
  // §8.14.1); −1: none. It must be below attributesRead − 1 where that is set.
  int derivativesOf = -1;
  // Whether the shader reads the fragment's depths (FragmentInput::depth, viewDepth). A batch
  // program that does not, with early tests and no depth writes, lets the pipeline skip the
  // window depth of the runs of a span that provably pass the depth test (pipeline/depth_bounds.h),
  // and, if it reads no attribute either (attributesRead 0) or only attributes that are the same at
  // a triangle's three vertices (where the pipeline proves that interpolation gives that value at
  // each of its pixels), their interpolation: their fragments reach the shader with NaN depths.
  // Which fragments reach it, and in which order, does not change.
  bool readsDepth = true;
  // With readsDepth: whether the shader reads FragmentInput::viewDepth as well. One that reads only
  // the window depth (gl_FragCoord.z) lets the pipeline take the window depth of a flat triangle
  // (one whose attributes are all equal at its vertices) from its plane, proven to round to the
  // same fp32 (pipeline/fragment_ops.h), where it proves the depth test passes; the view depth is
  // NaN there.
  bool readsViewDepth = true;
};

// A program whose per-fragment and batch shaders are the one callable
// shader(const FragmentInput&, FragmentOutput&).
template <typename Shader>
FragmentProgram programOf(Shader shader, bool mayDiscard = false, bool writesDepth = false,
                          bool earlyFragmentTests = false, bool pure = false) {
  FragmentProgram program{shader, mayDiscard, writesDepth, earlyFragmentTests, {}, pure};
  program.batch = [shader](const FragmentBatch& in, FragmentBatchOutput& out) {
    for (int i = 0; i < in.count; ++i) {
      FragmentOutput o = out.view(i);
      shader(in[i], o);
      out.finish(i, o);
    }
  };
  return program;
}

// A program from a batch shader, shader(const FragmentBatch&, FragmentBatchOutput&): the
// per-fragment shader runs it on a batch of one fragment, so that it stays the batch's oracle.
template <typename BatchShader>
FragmentProgram programOfBatch(BatchShader shader, bool mayDiscard = false, bool pure = false) {
  FragmentProgram program{[shader](const FragmentInput& in, FragmentOutput& out) {
                            FragmentBatchOutput batchOut;
                            batchOut.reset(1);
                            shader(FragmentBatch::of(in), batchOut);
                            batchOut.load(0, out);
                          },
                          mayDiscard, false, false, {}, pure};
  program.batch = std::move(shader);
  return program;
}

// texelFetch of image at each fragment's pixel, into out (Image::fetchRow); a run's texels as one
// stream (Image::fetchRun).
inline void fetchTexels(const Image& image, const FragmentBatch& in, glm::vec4* out) {
  if (in.run && in.count > 0) image.fetchRun(in.y, in.x[0], in.count, out);
  else image.fetchRow(in.y, in.x, in.count, out);
}
// fetchTexels's texels without the copy where the image holds them so (a run of an RGBA32F
// image: Image::float4Run), else fetched into scratch (kCapacity entries). The pointer is valid
// while the shader runs: blending writes after it. Copying a composite's fp32 texels was a tenth
// of its time.
inline const glm::vec4* texelsOf(const Image& image, const FragmentBatch& in, glm::vec4* scratch) {
  if (in.run && in.count > 0)
    if (const glm::vec4* texels = image.float4Run(in.y, in.x[0])) return texels;
  fetchTexels(image, in, scratch);
  return scratch;
}
// The red channels of fetchTexels's texels (fetch(x, y).r), in place for a run of an R32F image
// (Image::float1Run), else into scratch.
inline const float* redTexelsOf(const Image& image, const FragmentBatch& in, float* scratch) {
  if (in.run && in.count > 0)
    if (const float* reds = image.float1Run(in.y, in.x[0])) return reds;
  glm::vec4 texels[FragmentBatch::kCapacity];
  fetchTexels(image, in, texels);
  for (int i = 0; i < in.count; ++i) scratch[i] = texels[i].r;
  return scratch;
}

}  // namespace oitref
