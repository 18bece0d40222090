// The method kit: what an OIT method is written with, inside oitref or outside it. A method
// declares its attachments (AttachmentList, typed handles resolved once), draws its passes over
// the emulated pipeline (PassRunner), finds its attachments in the frame (FrameTargets) and, for
// most, lets OpaqueFirstMethod own the frame's skeleton. Registered with registerMethod
// (oitref/oit/method.h), it is rendered, studied and stressed like a built-in method:
// examples/custom_method does this from outside the source tree.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "oitref/oit/method.h"
#include "oitref/core/pipeline_state.h"
#include "oitref/core/shader.h"

namespace oitref {

// A declared attachment as a method's passes reach it: the place of its declaration in the
// method's AttachmentList, found when the method declares it, so that a frame looks up no names.
struct ColorHandle {
  int index = -1;
};
struct DepthHandle {
  int index = -1;
};

// What a method allocates at each pixel, in order. Every list starts with the two attachments
// of the opaque pass: "opaque" (RGBA8, cleared to the background; the composite lands here) and
// "depth" (d24, cleared to 1; transparent passes test against it).
class AttachmentList {
 public:
  AttachmentList();
  static constexpr ColorHandle kOpaque{0};
  static constexpr DepthHandle kDepth{1};
  // Throws std::invalid_argument for a name already declared or, from the string form, a format
  // name parseFormat does not know.
  ColorHandle color(std::string name, const Format& format, std::string purpose);
  ColorHandle color(std::string name, const std::string& format, std::string purpose);
  DepthHandle depth(std::string name, DepthFormat format, std::string purpose);
  // Declares that the composite does not read `handle` (AttachmentDecl::readByComposite).
  void readBeforeCompositeOnly(ColorHandle handle);
  const std::vector<AttachmentDecl>& declared() const { return declared_; }

 private:
  int add(AttachmentDecl decl);
  std::vector<AttachmentDecl> declared_;
};

// The declared attachments of one frame, allocated exactly, plus the RGBA32F analysis copy of
// the background (see oitref/oit/method.h).
class FrameTargets {
 public:
  // From context.pool when there is one (contents undefined), else newly allocated.
  FrameTargets(const std::vector<AttachmentDecl>& declared, const FrameContext& context);
  // Gives what the frame did not move into its result back to the pool.
  ~FrameTargets();
  FrameTargets(const FrameTargets&) = delete;
  FrameTargets& operator=(const FrameTargets&) = delete;
  // Throws std::logic_error for a handle the method did not declare (a default-made one).
  Image& operator[](ColorHandle handle);
  DepthBuffer& operator[](DepthHandle handle);
  Image& opaque() { return (*this)[AttachmentList::kOpaque]; }
  DepthBuffer& depth() { return (*this)[AttachmentList::kDepth]; }
  Image& analysis() { return analysis_; }
  // "opaque" as target 0 and the analysis copy as target 1 (and "depth" when asked): where a
  // method's result is presented.
  Framebuffer present(bool withDepth);
  // Moves every colour attachment, in declaration order, and the finals into the result; the
  // presented RGBA8 image is a copy of `final`.
  void finish(FrameResult& result, ColorHandle final);

 private:
  std::vector<std::string> names_;  // by declaration
  std::vector<bool> isDepth_;       // by declaration
  std::vector<size_t> slot_;        // by declaration: its place in colors_ or depths_
  std::vector<Image> colors_;
  std::vector<DepthBuffer> depths_;
  Image analysis_;
  AttachmentPool* pool_;
};

// The most fragments a batch shader (PassRunner::transparentBatchPass) gets in one call.
constexpr int kShaderBatch = FragmentBatch::kCapacity;

class PassRunner {
 public:
  PassRunner(const FrameContext& context, FrameResult& result) : context_(context), result_(result) {}
  const FrameContext& context() const { return context_; }
  glm::mat4 viewProjection() const;

  // Clears opaque (and the analysis copy) to the background and depth to 1, then draws the
  // opaque objects (every object when `everything`) with depth test LESS and writes; alpha 1.
  void opaquePass(FrameTargets& targets, bool everything = false);
  // Draws the transparent objects in submission order into fb with `state` (one draw sequence:
  // Renderer::drawSequence; FragmentInput::drawId is the object's index in the scene); the shader,
  // shader(const FragmentInput&, const glm::vec4& color, FragmentOutput&), gets each fragment's
  // straight colour from the object's shading function (shadeSurface, shared with the ray caster).
  // A template so that the method's shader is compiled into the fragment program (programOf): one
  // indirect call per batch of fragments, not one per fragment and layer of lambdas.
  // `pure`: FragmentProgram::pure (the shader has no effect but its outputs and discard).
  template <typename Shader>
  void transparentPass(const std::string& name, Framebuffer& fb, const PipelineState& state, const Shader& shader,
                       bool mayDiscard = false, bool pure = false) {
    drawTransparent(name, fb, state, [&](const SceneObject& object) {
      const TextureFiltering filtering = context_.profile.texture;
      FragmentProgram program = programOf([&object, &shader, filtering](const FragmentInput& in, FragmentOutput& out) {
        const glm::vec4 c =
            shadeSurface(object, in.attributes, in.attributeStride, in.derivatives, in.derivativeStride, filtering);
        if (surfaceDiscards(object, c)) return out.discard();
        shader(in, c, out);
      }, mayDiscard, false, false, pure);
      withSurfaceTest(program, object, state);
      return program;
    });
  }
  // The same with a shader over a batch of fragments of distinct pixels (FragmentBatch):
  // shader(const FragmentBatch& in, const glm::vec4* colors, FragmentBatchOutput& out), in.count ≤
  // kShaderBatch, for shaders whose arithmetic gains from seeing several fragments at once
  // (lanes). The per-fragment program calls it with a batch of one, so it stays the batch's oracle.
  // `discardTest`: the shader's own depth test (FragmentProgram::discardTest; needs `pure`).
  // `readsDepth` false: the shader reads neither in.depth nor in.viewDepth, so the pipeline need
  // not compute the window depth where it proves the depth test passes (FragmentProgram::readsDepth);
  // `readsViewDepth` false: it reads in.depth but not in.viewDepth (FragmentProgram::readsViewDepth).
  template <typename BatchShader>
  void transparentBatchPass(const std::string& name, Framebuffer& fb, const PipelineState& state,
                            const BatchShader& shader, bool mayDiscard = false, bool pure = false,
                            const ShaderDepthTest& discardTest = {}, bool readsDepth = true, bool readsViewDepth = true,
                            const TileBands& bands = {}) {
    drawTransparent(name, fb, state, [&](const SceneObject& object) {
      const TextureFiltering filtering = context_.profile.texture;
      FragmentProgram program = programOfBatch(
          [&object, &shader, filtering](const FragmentBatch& in, FragmentBatchOutput& out) {
            if (in.count <= 0) return;  // never: it tells the compiler the rows below are set
            glm::vec4 colors[kShaderBatch];
            shadeSurfaceBatch(object, in.attributes, in.attributeStride, in.derivatives, in.derivativeStride, filtering,
                              in.count, colors, in.uniformAttributes);
            if (!object.alphaTest) return shader(in, colors, out);
            // The alpha test's survivors, each as a batch of one (the shader must not see the
            // others: it may store what it sees).
            for (int i = 0; i < in.count; ++i) {
              if (surfaceDiscards(object, colors[i])) {
                out.discard(i);
                continue;
              }
              const FragmentInput one = in[i];
              FragmentBatchOutput oneOut;
              oneOut.reset(1);
              shader(FragmentBatch::of(one), &colors[i], oneOut);
              FragmentOutput result;
              oneOut.load(0, result);
              out.store(i, result);
            }
          },
          mayDiscard, pure);
      program.discardTest = discardTest;
      program.readsDepth = readsDepth;
      program.readsViewDepth = readsViewDepth;
      withSurfaceTest(program, object, state);
      return program;
    }, bands);
  }
  // A pass whose shader reads nothing of the surface — only each fragment's position, depths and
  // ids: shader(const FragmentBatch& in, FragmentBatchOutput& out). No attribute is interpolated,
  // except for an alpha-tested object: its fragments that fail the test are discarded first, as
  // in every other pass (a discarded texel is no surface in any pass). `readsDepth` false: the
  // shader reads only the fragments' columns, row and ids, so the pipeline need not interpolate
  // where it can prove the depth test passes (FragmentProgram::readsDepth; the depths are NaN).
  template <typename BatchShader>
  void transparentPositionPass(const std::string& name, Framebuffer& fb, const PipelineState& state,
                               const BatchShader& shader, bool readsDepth = true) {
    drawTransparent(name, fb, state, [&](const SceneObject& object) {
      if (object.alphaTest)
        return alphaTestedPositionProgram(object, state, context_.profile.texture, [&shader](const FragmentBatch& in, FragmentBatchOutput& out) { shader(in, out); });
      FragmentProgram program = programOfBatch([&shader](const FragmentBatch& in, FragmentBatchOutput& out) { shader(in, out); });
      program.attributesRead = 0;
      program.readsDepth = readsDepth;
      return program;
    });
  }
  // The part's vertices through the vertex stage (toClipGeometry), computed once per frame: every
  // pass of a frame draws the same clip-space geometry (peeling draws it once per layer).
  const Geometry& clipGeometry(const ScenePart& part);
  // The composite of the weighted methods (thesis Algorithms 3, 4, 6): a full-screen pass whose
  // shader returns (colour, T) — or nothing to keep the background — blended into "opaque" and
  // the analysis copy with C = C_s·(1 − α_s) + C_d·α_s (alpha kept).
  // source(const FragmentInput&, glm::vec4& colourAndT) -> bool.
  template <typename Source>
  void blendOverBackground(FrameTargets& targets, const Source& source) {
    Framebuffer out = targets.present(false);
    fullscreenPass("composite", out, compositeState(), [&source](const FragmentInput& in, FragmentOutput& o) {
      glm::vec4 s;
      if (!source(in, s)) return;
      o.write(0, s);
      o.write(1, s);
    });
  }
  // The same with a source over a batch: source(const FragmentBatch& in, glm::vec4* colourAndT)
  // sets every fragment's (colour, T).
  template <typename BatchSource>
  void blendOverBackgroundBatch(FrameTargets& targets, const BatchSource& source) {
    Framebuffer out = targets.present(false);
    fullscreenProgram("composite", out, compositeState(),
                      programOfBatch([&source](const FragmentBatch& in, FragmentBatchOutput& o) {
                        glm::vec4 s[kShaderBatch];
                        source(in, s);
                        for (int i = 0; i < in.count; ++i) o.write(i, 0, s[i]), o.write(i, 1, s[i]);
                      }));
  }
  // The composite of the methods that blend in the shader (A-buffer, hybrid, MLAB, DFAOIT): a
  // full-screen pass named `name` whose `resolve` gets the pixel's background in each presented
  // target — [0] the RGBA8 "opaque", [1] the RGBA32F analysis copy — and returns the composite
  // over each in result[0], result[1] (written with alpha 1), or false to keep both.
  using ShaderComposite = std::function<bool(const FragmentInput&, const glm::vec3 background[2], glm::vec3 result[2])>;
  void compositeOntoBackgrounds(FrameTargets& targets, const std::string& name, const ShaderComposite& resolve);
  // The same over a batch of one row's pixels (FragmentBatch, in.count ≤ kShaderBatch), for a
  // resolve that gains from seeing several pixels at once (the A-buffer sorts two pixels' lists
  // side by side): resolve(in, background, result, resolved) gets pixel in.x[i]'s backgrounds in
  // background[0][i], background[1][i], and sets result[0][i], result[1][i] and resolved[i]
  // (false: keep both backgrounds).
  using ShaderCompositeBatch = std::function<void(const FragmentBatch& in, const glm::vec3* const background[2],
                                                  glm::vec3* const result[2], bool* resolved)>;
  void compositeOntoBackgroundsBatch(FrameTargets& targets, const std::string& name, const ShaderCompositeBatch& resolve);
  // One full-screen pass; shader(const FragmentInput&, FragmentOutput&), compiled into a batch
  // program (programOf).
  template <typename Shader>
  void fullscreenPass(const std::string& name, Framebuffer& fb, const PipelineState& state, const Shader& shader) {
    fullscreenProgram(name, fb, state, programOf(shader));
  }
  void fullscreenProgram(const std::string& name, Framebuffer& fb, const PipelineState& state,
                         const FragmentProgram& program);

 private:
  const FrameContext& context_;
  FrameResult& result_;
  // transparentPass's body: programFor(object) is the fragment program of the object's draw; one
  // that does not say how many attributes it reads reads those of shadeSurface.
  void drawTransparent(const std::string& name, Framebuffer& fb, const PipelineState& state,
                       const std::function<FragmentProgram(const SceneObject&)>& programFor,
                       const TileBands& bands = {});
  PipelineState compositeState() const;  // compositeBlend() on both presented targets
  // What a program through shadeSurface declares for `object` (scene_geometry.h): the attributes
  // and derivatives it reads and, for an alpha-tested object, that it may discard. A shader that
  // did not discard before keeps its early depth test where the pass writes no depth (as GLSL's
  // layout(early_fragment_tests) would: a shader that stores what it sees — the A-buffer's lists
  // — must not see the fragments behind the opaque surfaces).
  static void withSurfaceTest(FragmentProgram& program, const SceneObject& object, const PipelineState& state);
  using PositionShader = std::function<void(const FragmentBatch&, FragmentBatchOutput&)>;
  static FragmentProgram alphaTestedPositionProgram(const SceneObject& object, const PipelineState& state,
                                                    TextureFiltering filtering, PositionShader shader);

  std::vector<std::unique_ptr<Geometry>> clipGeometry_;  // per part of context_.geometry, on first use
};


// The frame most methods draw: their attachments (from the pool, or new), the opaque pass (the
// background cleared, the opaque objects drawn with depth test LESS), then the method's own
// passes in drawAfterOpaque, and the frame presented from `presented` with every attachment in
// the result. A method whose frame starts otherwise (the A-buffer refuses some frames before
// anything is allocated) derives from Method itself.
class OpaqueFirstMethod : public Method {
 public:
  std::vector<AttachmentDecl> attachments() const final { return declared.declared(); }
  FrameResult render(const FrameContext& context) final {
    FrameResult result;
    FrameTargets targets(declared.declared(), context);
    PassRunner run(context, result);
    run.opaquePass(targets);
    drawAfterOpaque(context, run, targets, result);
    targets.finish(result, presented);
    return result;
  }

 protected:
  // The method's passes; `result` is for its stats (the passes' reports are kept by `run`).
  virtual void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& result) = 0;
  AttachmentList declared;                        // the method's constructor declares the rest
  ColorHandle presented = AttachmentList::kOpaque;  // the attachment the frame presents
};

// The blend states of the methods, named once so the emulated passes and their GL mirrors
// (glcheck) use the same objects.
BlendState overBlend();       // OVER: src_alpha, one_minus_src_alpha; alpha one, one_minus_src_alpha
BlendState additiveBlend();   // Σ: one, one
BlendState revealageBlend();  // Π(1 − α): zero, one_minus_src_color
// C = C_s·(1 − α_s) + C_d·α_s, alpha kept: one_minus_src_alpha, src_alpha; alpha zero, one.
BlendState compositeBlend();
// Front-to-back "under" (peeling): RGB C_s·α_d + C_d, alpha α_d·(1 − α_s): dst_alpha, one; zero, one_minus_src_alpha.
BlendState underBlend();
// McGuire–Bavoil listing 4, one function for every target: RGB one, one; alpha zero, one_minus_src_alpha.
BlendState singleTargetWeightedBlend();
// Premultiplied layers onto the background: C_s + C_d·α_s, alpha kept: one, src_alpha; zero, one.
BlendState premultipliedOntoBackgroundBlend();
// Depth state of the transparent passes: test LESS against the opaque depth, no writes.
DepthState transparentDepth();
// A transparent pass's state: the profile, transparentDepth(), and `blend` on targets 0 and 1.
PipelineState transparentState(const Profile& profile, const BlendState& blend);


}  // namespace oitref
