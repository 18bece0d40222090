// The method kit (oitref/oit/method_kit.h): declared attachments, a frame's targets, the passes.
#include "oitref/oit/method_kit.h"

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "blend/method_blend_states.h"

namespace oitref {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

AttachmentList::AttachmentList() {
  color("opaque", "rgba8", "opaque background; the composite lands here");
  depth("depth", DepthFormat::D24, "opaque depth; transparent passes test against it");
}

int AttachmentList::add(AttachmentDecl decl) {
  for (const AttachmentDecl& d : declared_)
    if (d.name == decl.name) throw std::invalid_argument("attachment '" + decl.name + "' is declared twice");
  declared_.push_back(std::move(decl));
  return int(declared_.size()) - 1;
}

ColorHandle AttachmentList::color(std::string name, const Format& format, std::string purpose) {
  AttachmentDecl d;
  d.name = std::move(name);
  d.format = format;
  d.purpose = std::move(purpose);
  return {add(std::move(d))};
}

ColorHandle AttachmentList::color(std::string name, const std::string& format, std::string purpose) {
  return color(std::move(name), parseFormat(format), std::move(purpose));
}

void AttachmentList::readBeforeCompositeOnly(ColorHandle handle) {
  declared_.at(size_t(handle.index)).readByComposite = false;
}

DepthHandle AttachmentList::depth(std::string name, DepthFormat format, std::string purpose) {
  AttachmentDecl d;
  d.name = std::move(name);
  d.isDepth = true;
  d.readByComposite = false;
  d.depthFormat = format;
  d.purpose = std::move(purpose);
  return {add(std::move(d))};
}

FrameTargets::FrameTargets(const std::vector<AttachmentDecl>& declared, const FrameContext& context)
    : pool_(context.pool) {
  const int w = context.width, h = context.height;
  // Shaders fetch the attachments as the profile's texture unit converts them (Image::decodeFetchesAs).
  auto image = [&](const Format& f) {
    Image i = pool_ ? pool_->takeImage(f, w, h) : Image(f, w, h);
    i.decodeFetchesAs(context.profile.texture);
    return i;
  };
  analysis_ = image(makeFormat(FormatId::RGBA32F));
  for (const AttachmentDecl& d : declared) {
    names_.push_back(d.name);
    isDepth_.push_back(d.isDepth);
    slot_.push_back(d.isDepth ? depths_.size() : colors_.size());
    if (d.isDepth) depths_.push_back(pool_ ? pool_->takeDepth(d.depthFormat, w, h) : DepthBuffer(d.depthFormat, w, h));
    else colors_.push_back(image(d.format));
  }
}

FrameTargets::~FrameTargets() {
  if (!pool_) return;
  for (DepthBuffer& depth : depths_) pool_->give(std::move(depth));
  for (Image& image : colors_) pool_->give(std::move(image));
  pool_->give(std::move(analysis_));
}

Image& FrameTargets::operator[](ColorHandle handle) {
  if (handle.index < 0 || size_t(handle.index) >= names_.size() || isDepth_[size_t(handle.index)])
    throw std::logic_error("method uses a colour attachment it did not declare (handle " + std::to_string(handle.index) + ")");
  return colors_[slot_[size_t(handle.index)]];
}

DepthBuffer& FrameTargets::operator[](DepthHandle handle) {
  if (handle.index < 0 || size_t(handle.index) >= names_.size() || !isDepth_[size_t(handle.index)])
    throw std::logic_error("method uses a depth attachment it did not declare (handle " + std::to_string(handle.index) + ")");
  return depths_[slot_[size_t(handle.index)]];
}

Framebuffer FrameTargets::present(bool withDepth) {
  Framebuffer fb;
  fb.color[0] = &opaque();
  fb.color[1] = &analysis_;
  if (withDepth) fb.depth = &depth();
  return fb;
}

void FrameTargets::finish(FrameResult& result, ColorHandle final) {
  const Image& final8 = (*this)[final];
  // A copy: into a pooled image of the same size, whose storage the copy reuses.
  if (pool_) result.final8 = pool_->takeImage(final8.format(), final8.width(), final8.height());
  result.final8 = final8;
  result.finalFloat = std::move(analysis_);
  for (size_t i = 0; i < names_.size(); ++i)
    if (!isDepth_[i]) result.dump.emplace_back(names_[i], std::move(colors_[slot_[i]]));
  // The result is read as stored values (metrics, files, comparisons): exact decoding again.
  result.final8.decodeFetchesAs(TextureFiltering::Exact);
  for (auto& [name, image] : result.dump) image.decodeFetchesAs(TextureFiltering::Exact);
}

glm::mat4 PassRunner::viewProjection() const { return context_.viewProjection(); }

void PassRunner::opaquePass(FrameTargets& targets, bool everything) {
  const auto t0 = std::chrono::steady_clock::now();
  Image& opaque = targets.opaque();
  const glm::vec4 background(context_.scene.background, 1.0f);
  Framebuffer fb;
  fb.color[0] = &opaque;
  fb.color[1] = &targets.analysis();
  fb.depth = &targets.depth();
  // Cleared by the draw, tile by tile (Framebuffer::clearColor).
  fb.clearColor[0] = fb.clearColor[1] = background;
  fb.clearDepth = 1.0;
  PipelineState st;
  st.profile = context_.profile;
  st.depth = {true, CompareFunc::Less, true, false};
  PassReport report{"opaque", 0, {}};
  std::vector<Renderer::DrawCall> draws;
  for (const ScenePart& part : context_.geometry.parts) {
    if (part.transparent && !everything) continue;
    const SceneObject& object = context_.scene.objects[part.objectIndex];
    // A batch shader (shadeSurfaceBatch: a flat triangle's colour once); the per-fragment path runs
    // it on batches of one.
    FragmentProgram program = programOfBatch([&object, filtering = context_.profile.texture](const FragmentBatch& in,
                                                                                           FragmentBatchOutput& out) {
      if (in.count <= 0) return;  // never: it tells the compiler the rows below are set
      glm::vec4 colors[kShaderBatch];
      shadeSurfaceBatch(object, in.attributes, in.attributeStride, in.derivatives, in.derivativeStride, filtering, in.count,
                        colors, in.uniformAttributes);
      for (int i = 0; i < in.count; ++i) {
        if (surfaceDiscards(object, colors[i])) {
          out.discard(i);
          continue;
        }
        const glm::vec4 opaqueColour{glm::vec3(colors[i]), 1.0f};
        out.write(i, 0, opaqueColour);
        out.write(i, 1, opaqueColour);
      }
    });
    withSurfaceTest(program, object, st);
    draws.push_back({&clipGeometry(part), std::move(program), uint32_t(part.objectIndex)});
  }
  report.stats = context_.renderer.drawSequence(fb, st, draws);
  report.ms = msSince(t0);
  result_.passes.push_back(report);
}

const Geometry& PassRunner::clipGeometry(const ScenePart& part) {
  const std::vector<ScenePart>& parts = context_.geometry.parts;
  const size_t i = size_t(&part - parts.data());
  if (i >= parts.size()) throw std::logic_error("clipGeometry: the part is not one of the frame's scene geometry");
  if (clipGeometry_.size() != parts.size()) clipGeometry_.resize(parts.size());
  if (!clipGeometry_[i]) clipGeometry_[i] = std::make_unique<Geometry>(toClipGeometry(part, viewProjection()));
  return *clipGeometry_[i];
}

void PassRunner::withSurfaceTest(FragmentProgram& program, const SceneObject& object, const PipelineState& state) {
  if (program.attributesRead < 0) program.attributesRead = shadeSurfaceReads(object);
  program.derivativesOf = shadeSurfaceDerivatives(object);
  if (!object.alphaTest || program.mayDiscard) return;
  program.mayDiscard = true;
  const bool writesDepth = state.depth.testEnabled && state.depth.writeMask;
  if (!program.pure && !writesDepth) program.earlyFragmentTests = true;
}

FragmentProgram PassRunner::alphaTestedPositionProgram(const SceneObject& object, const PipelineState& state,
                                                      TextureFiltering filtering, PositionShader shader) {
  FragmentProgram program = programOf([&object, filtering, shader](const FragmentInput& in, FragmentOutput& out) {
    const glm::vec4 c = shadeSurface(object, in.attributes, in.attributeStride, in.derivatives, in.derivativeStride, filtering);
    if (surfaceDiscards(object, c))
      return out.discard();
    FragmentBatchOutput one;
    one.reset(1);
    shader(FragmentBatch::of(in), one);
    one.load(0, out);
  });
  withSurfaceTest(program, object, state);
  return program;
}

void PassRunner::drawTransparent(const std::string& name, Framebuffer& fb, const PipelineState& state,
                                 const std::function<FragmentProgram(const SceneObject&)>& programFor,
                                 const TileBands& bands) {
  const auto t0 = std::chrono::steady_clock::now();
  PassReport report{name, 0, {}};
  std::vector<Renderer::DrawCall> draws;
  for (const ScenePart& part : context_.geometry.parts) {
    if (!part.transparent) continue;
    const SceneObject& object = context_.scene.objects[part.objectIndex];
    FragmentProgram program = programFor(object);
    if (program.attributesRead < 0) program.attributesRead = shadeSurfaceReads(object);  // through shadeSurface
    draws.push_back({&clipGeometry(part), std::move(program), uint32_t(part.objectIndex)});
  }
  report.stats = context_.renderer.drawSequence(fb, state, draws, bands);
  report.ms = msSince(t0);
  result_.passes.push_back(report);
}

void PassRunner::fullscreenProgram(const std::string& name, Framebuffer& fb, const PipelineState& state,
                                   const FragmentProgram& program) {
  const auto t0 = std::chrono::steady_clock::now();
  PassReport report{name, 0, context_.renderer.drawFullscreen(fb, state, program)};
  report.ms = msSince(t0);
  result_.passes.push_back(report);
}

PipelineState PassRunner::compositeState() const {
  PipelineState composite;
  composite.profile = context_.profile;
  composite.blend[0] = composite.blend[1] = compositeBlend();
  return composite;
}

void PassRunner::compositeOntoBackgrounds(FrameTargets& targets, const std::string& name, const ShaderComposite& resolve) {
  compositeOntoBackgroundsBatch(targets, name, [&resolve](const FragmentBatch& in, const glm::vec3* const background[2],
                                                          glm::vec3* const result[2], bool* resolved) {
    for (int i = 0; i < in.count; ++i) {
      const glm::vec3 pixelBackground[2] = {background[0][i], background[1][i]};
      glm::vec3 pixelResult[2];
      resolved[i] = resolve(in[i], pixelBackground, pixelResult);
      result[0][i] = pixelResult[0], result[1][i] = pixelResult[1];
    }
  });
}

void PassRunner::compositeOntoBackgroundsBatch(FrameTargets& targets, const std::string& name,
                                               const ShaderCompositeBatch& resolve) {
  Framebuffer out = targets.present(false);
  PipelineState plain;
  plain.profile = context_.profile;
  const Image& opaque = targets.opaque();
  const Image& analysis = targets.analysis();
  fullscreenProgram(name, out, plain, programOfBatch([&](const FragmentBatch& in, FragmentBatchOutput& o) {
    glm::vec4 texels[kShaderBatch];
    glm::vec3 background[2][kShaderBatch], result[2][kShaderBatch];
    bool resolved[kShaderBatch];
    for (int t = 0; t < 2; ++t) {
      fetchTexels(t == 0 ? opaque : analysis, in, texels);
      for (int i = 0; i < in.count; ++i) background[t][i] = glm::vec3(texels[i]);
    }
    const glm::vec3* const backgrounds[2] = {background[0], background[1]};
    glm::vec3* const results[2] = {result[0], result[1]};
    resolve(in, backgrounds, results, resolved);
    for (int i = 0; i < in.count; ++i)
      if (resolved[i]) {
        o.write(i, 0, glm::vec4(result[0][i], 1.0f));
        o.write(i, 1, glm::vec4(result[1][i], 1.0f));
      }
  }));
}

BlendState overBlend() { return detail::states::kOver; }
BlendState additiveBlend() { return detail::states::kAdditive; }
BlendState revealageBlend() { return detail::states::kRevealage; }
BlendState singleTargetWeightedBlend() { return detail::states::kSingleTargetWeighted; }
BlendState compositeBlend() { return detail::states::kComposite; }
BlendState underBlend() { return detail::states::kUnder; }
BlendState premultipliedOntoBackgroundBlend() { return detail::states::kPremultipliedOntoBackground; }

DepthState transparentDepth() { return {true, CompareFunc::Less, false, false}; }

PipelineState transparentState(const Profile& profile, const BlendState& blend) {
  PipelineState st;
  st.profile = profile;
  st.depth = transparentDepth();
  st.blend.fill(blend);  // every target: a pass that binds a third one blends it too
  return st;
}

}  // namespace oitref
