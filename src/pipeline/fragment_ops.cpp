#include "pipeline/fragment_ops.h"


namespace oitref::detail {

FragmentStage::FragmentStage(Framebuffer& fb, const PipelineState& state, const FragmentProgram& program,
                             const Geometry* geometry)
    : fb_(fb), state_(state), program_(program), geometry_(geometry) {
  earlyTests_ = program.earlyFragmentTests || !(program.mayDiscard || program.writesDepth);
  blenders_.reserve(kMaxColorTargets);
  for (int t = 0; t < kMaxColorTargets; ++t) {
    if (fb.color[size_t(t)]) boundTargets_ |= 1u << t;
    blenders_.emplace_back(fb.color[size_t(t)] ? fb.color[size_t(t)]->format() : Format{}, state.blend[size_t(t)],
                           state.blendConstant, state.profile);
  }
  const int n = geometry ? geometry->attributeCount : 0;
  vertexAttributes_.assign(size_t(3 * n), 0.0);
  attributes_.assign(size_t(n), 0.0f);
}

void FragmentStage::beginTriangle(const SetupTriangle& t, const std::vector<ClipBarycentrics>& clipBarycentrics) {
  triangle_ = &t;
  const int n = geometry_->attributeCount;
  if (n == 0) return;
  if (t.clipSlot < 0) {
    for (int i = 0; i < 3; ++i) {
      const float* a = geometry_->vertexAttributes(t.vertexIndex[i]);
      for (int k = 0; k < n; ++k) vertexAttributes_[size_t(i * n + k)] = a[k];
    }
    return;
  }
  const ClipBarycentrics& cb = clipBarycentrics[size_t(t.clipSlot)];
  const float* src[3] = {geometry_->vertexAttributes(t.vertexIndex[0]), geometry_->vertexAttributes(t.vertexIndex[1]),
                         geometry_->vertexAttributes(t.vertexIndex[2])};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < n; ++k)
      vertexAttributes_[size_t(i * n + k)] = cb.b[i][0] * src[0][k] + cb.b[i][1] * src[1][k] + cb.b[i][2] * src[2][k];
}

void FragmentStage::interpolateAttributes(const double* b) {
  const int n = int(attributes_.size());
  const double* va = vertexAttributes_.data();
  for (int k = 0; k < n; ++k) attributes_[size_t(k)] = float(b[0] * va[k] + b[1] * va[n + k] + b[2] * va[2 * n + k]);
}

void FragmentStage::fragment(int x, int y, const int64_t e[3]) {
  const SetupTriangle& t = *triangle_;
  const double l0 = double(e[0]) * t.invArea2, l1 = double(e[1]) * t.invArea2, l2 = double(e[2]) * t.invArea2;
  const double z = l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2];
  const double p0 = l0 * t.invW[0], p1 = l1 * t.invW[1], p2 = l2 * t.invW[2];
  const double w = 1.0 / (p0 + p1 + p2);
  const double b[3] = {p0 * w, p1 * w, p2 * w};
  const int n = int(attributes_.size());

  FragmentInput in;
  in.x = x;
  in.y = y;
  in.fragCoord = {float(x) + 0.5f, float(y) + 0.5f};
  in.depth = float(z);
  in.viewDepth = float(w);
  in.frontFacing = t.frontFacing;
  in.primitiveId = t.primitiveId;
  in.attributes = attributes_.data();
  in.attributeCount = n;
  ++counters_.rasterized;
  process(in, z, b);
}

void FragmentStage::fullscreenPixel(int x, int y) {
  FragmentInput in;
  in.x = x;
  in.y = y;
  in.fragCoord = {float(x) + 0.5f, float(y) + 0.5f};
  in.depth = 0.0f;
  in.viewDepth = 1.0f;
  ++counters_.rasterized;
  process(in, 0.0, nullptr);
}

// Attributes are interpolated only for fragments that reach the shader.
void FragmentStage::process(FragmentInput& in, double z, const double* perspectiveBary) {
  DepthBuffer* depth = fb_.depth;
  const DepthState& ds = state_.depth;
  const bool testing = depth != nullptr && ds.testEnabled;  // GL §17.3.4: no test, no depth write
  uint32_t fragmentDepth = testing ? encodeDepth(z, depth->format()) : 0;

  if (testing && earlyTests_) {
    if (!depthTestPasses(ds.func, fragmentDepth, depth->load(in.x, in.y), depth->format())) {
      ++counters_.depthFailed;
      return;
    }
    if (ds.writeMask) depth->store(in.x, in.y, fragmentDepth);
  }

  if (perspectiveBary) interpolateAttributes(perspectiveBary);
  output_.reset();
  program_.shader(in, output_);
  ++counters_.shaded;
  if (output_.discarded()) {
    ++counters_.discarded;
    return;
  }

  if (testing && !earlyTests_) {
    if (output_.depthWritten()) fragmentDepth = encodeDepth(double(output_.depth()), depth->format());
    if (!depthTestPasses(ds.func, fragmentDepth, depth->load(in.x, in.y), depth->format())) {
      ++counters_.depthFailed;
      return;
    }
    if (ds.writeMask) depth->store(in.x, in.y, fragmentDepth);
  }

  unsigned targets = output_.writtenMask() & boundTargets_;
  if (targets) ++counters_.written;
  while (targets) {
    const int t = __builtin_ctz(targets);
    targets &= targets - 1;
    blenders_[size_t(t)].blend(output_.color(t), fb_.color[size_t(t)]->texel(in.x, in.y));
  }
}

}  // namespace oitref::detail
