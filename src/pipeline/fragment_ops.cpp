#include "pipeline/fragment_ops.h"


namespace oitref::detail {

FragmentStage::FragmentStage(Framebuffer& fb, const PipelineState& state, const FragmentProgram& program,
                             const Geometry* geometry, const PixelRect& viewport)
    : fb_(fb), state_(state), program_(program), geometry_(geometry) {
  earlyTests_ = program.earlyFragmentTests || !(program.mayDiscard || program.writesDepth);
  blenders_.reserve(kMaxColorTargets);
  bool smallFloatBound = false;  // llvmpipe keeps denormals for the whole draw then
  for (int t = 0; t < kMaxColorTargets; ++t)
    if (fb.color[size_t(t)]) smallFloatBound |= isSmallFloatFormat(fb.color[size_t(t)]->format());
  for (int t = 0; t < kMaxColorTargets; ++t) {
    if (fb.color[size_t(t)]) boundTargets_ |= 1u << t;
    blenders_.emplace_back(fb.color[size_t(t)] ? fb.color[size_t(t)]->format() : Format{}, state.blend[size_t(t)],
                           state.blendConstant, state.profile, true, smallFloatBound);
  }
  const int n = geometry ? geometry->attributeCount : 0;
  vertexAttributes_.assign(size_t(3 * n), 0.0);
  attributes_.assign(size_t(n), 0.0f);
  // x_n = (x + ½ − vx)·(2/vw) − 1
  const double vw = viewport.x1 - viewport.x0, vh = viewport.y1 - viewport.y0;
  ndcScaleX_ = 2.0 / vw, ndcOffsetX_ = (0.5 - viewport.x0) * (2.0 / vw) - 1.0;
  ndcScaleY_ = 2.0 / vh, ndcOffsetY_ = (0.5 - viewport.y0) * (2.0 / vh) - 1.0;
}

void FragmentStage::beginTriangle(const SetupTriangle& t) {
  triangle_ = &t;
  glm::dvec4 v[3];
  for (int i = 0; i < 3; ++i) v[i] = glm::dvec4(geometry_->clipPositions[t.vertexIndex[i]]);
  // M has columns (x_i, y_i, w_i); M⁻¹ = adj(M) / det(M).
  const double m[3][3] = {{v[0].x, v[1].x, v[2].x}, {v[0].y, v[1].y, v[2].y}, {v[0].w, v[1].w, v[2].w}};
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1], c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2],
               c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  degenerate_ = det == 0.0;
  if (!degenerate_) {
    const double r = 1.0 / det;
    inverse_[0][0] = c00 * r, inverse_[1][0] = c01 * r, inverse_[2][0] = c02 * r;
    inverse_[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * r;
    inverse_[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * r;
    inverse_[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * r;
    inverse_[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * r;
    inverse_[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * r;
    inverse_[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * r;
  }
  for (int i = 0; i < 3; ++i) clipZ_[i] = v[i].z;
  const int n = geometry_->attributeCount;
  for (int i = 0; i < 3; ++i) {
    const float* a = geometry_->vertexAttributes(t.vertexIndex[i]);
    for (int k = 0; k < n; ++k) vertexAttributes_[size_t(i * n + k)] = a[k];
  }
}

void FragmentStage::interpolateAttributes(const double* b) {
  const int n = int(attributes_.size());
  const double* va = vertexAttributes_.data();
  for (int k = 0; k < n; ++k) attributes_[size_t(k)] = float(b[0] * va[k] + b[1] * va[n + k] + b[2] * va[2 * n + k]);
}

void FragmentStage::fragment(int x, int y) {
  if (degenerate_) return;
  const SetupTriangle& t = *triangle_;
  const double xn = double(x) * ndcScaleX_ + ndcOffsetX_, yn = double(y) * ndcScaleY_ + ndcOffsetY_;
  double k[3];
  for (int i = 0; i < 3; ++i) k[i] = inverse_[i][0] * xn + inverse_[i][1] * yn + inverse_[i][2];
  const double w = 1.0 / (k[0] + k[1] + k[2]);  // P.w, the view depth
  const double b[3] = {k[0] * w, k[1] * w, k[2] * w};
  const double clipZ = b[0] * clipZ_[0] + b[1] * clipZ_[1] + b[2] * clipZ_[2];
  const double z = 0.5 * (clipZ / w) + 0.5;
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
