// What every OIT method shares: its declared attachments, allocated exactly; the opaque pass;
// drawing the transparent objects in submission order (object order, then triangle order);
// and the full-screen composite. Each method file then reads like its paper's pseudocode.
#pragma once

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "methods/power.h"
#include "oitref/method.h"

namespace oitref::methods {

// The declared attachments of one frame, allocated exactly, plus the RGBA32F analysis copy of
// the background ("opaque_float", see oitref/method.h).
class FrameTargets {
 public:
  // From context.pool when there is one (contents undefined), else newly allocated.
  FrameTargets(const std::vector<AttachmentDecl>& declared, const FrameContext& context);
  // Gives what the frame did not move into its result back to the pool.
  ~FrameTargets();
  FrameTargets(const FrameTargets&) = delete;
  FrameTargets& operator=(const FrameTargets&) = delete;
  Image& color(const std::string& name);
  DepthBuffer& depth(const std::string& name);
  Image& analysis() { return analysis_; }
  // "opaque" as target 0 and the analysis copy as target 1 (and "depth" when asked): where a
  // method's result is presented.
  Framebuffer present(bool withDepth);
  // Moves every colour attachment and the finals into the result.
  void finish(FrameResult& result, const std::string& finalName);

 private:
  std::map<std::string, Image> colors_;
  std::map<std::string, DepthBuffer> depths_;
  std::vector<std::string> order_;
  Image analysis_;
  AttachmentPool* pool_;
};

inline AttachmentDecl colorAttachment(std::string name, const std::string& format, std::string purpose) {
  AttachmentDecl d;
  d.name = std::move(name);
  d.format = parseFormat(format);
  d.purpose = std::move(purpose);
  return d;
}
inline AttachmentDecl depthAttachment(std::string name, std::string purpose) {
  AttachmentDecl d;
  d.name = std::move(name);
  d.isDepth = true;
  d.depthFormat = DepthFormat::D24;
  d.purpose = std::move(purpose);
  return d;
}
// "opaque" RGBA8 and "depth" d24: the start of every method's list.
std::vector<AttachmentDecl> opaqueAttachments();

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
  template <typename BatchShader>
  void transparentBatchPass(const std::string& name, Framebuffer& fb, const PipelineState& state,
                            const BatchShader& shader, bool mayDiscard = false, bool pure = false,
                            const ShaderDepthTest& discardTest = {}) {
    drawTransparent(name, fb, state, [&](const SceneObject& object) {
      const TextureFiltering filtering = context_.profile.texture;
      FragmentProgram program = programOfBatch(
          [&object, &shader, filtering](const FragmentBatch& in, FragmentBatchOutput& out) {
            if (in.count <= 0) return;  // never: it tells the compiler the rows below are set
            glm::vec4 colors[kShaderBatch];
            shadeSurfaceBatch(object, in.attributes, in.attributeStride, in.derivatives, in.derivativeStride, filtering,
                              in.count, colors);
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
      withSurfaceTest(program, object, state);
      return program;
    });
  }
  // A pass whose shader reads nothing of the surface — only each fragment's position, depths and
  // ids: shader(const FragmentBatch& in, FragmentBatchOutput& out). No attribute is interpolated,
  // except for an alpha-tested object: its fragments that fail the test are discarded first, as
  // in every other pass (a discarded texel is no surface in any pass).
  template <typename BatchShader>
  void transparentPositionPass(const std::string& name, Framebuffer& fb, const PipelineState& state,
                               const BatchShader& shader) {
    drawTransparent(name, fb, state, [&](const SceneObject& object) {
      if (object.alphaTest)
        return alphaTestedPositionProgram(object, state, context_.profile.texture, [&shader](const FragmentBatch& in, FragmentBatchOutput& out) { shader(in, out); });
      FragmentProgram program = programOfBatch([&shader](const FragmentBatch& in, FragmentBatchOutput& out) { shader(in, out); });
      program.attributesRead = 0;
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
                       const std::function<FragmentProgram(const SceneObject&)>& programFor);
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
// passes in drawAfterOpaque, and the frame presented from "opaque" with every attachment in the
// result. A method whose frame starts otherwise (the A-buffer refuses some frames before
// anything is allocated) derives from Method itself.
class OpaqueFirstMethod : public Method {
 public:
  FrameResult render(const FrameContext& context) final {
    FrameResult result;
    FrameTargets targets(attachments(), context);
    PassRunner run(context, result);
    run.opaquePass(targets);
    drawAfterOpaque(context, run, targets, result);
    targets.finish(result, "opaque");
    return result;
  }

 protected:
  // The method's passes; `result` is for its stats (the passes' reports are kept by `run`).
  virtual void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& result) = 0;
};

// The one-channel format with the same encoding as an RGBA one: "rgba16f" → "r16f",
// "rgba:e8m7" → "r:e8m7" (a count or revealage beside an accumulation target).
inline std::string singleChannelFormat(const std::string& rgbaFormat) { return "r" + rgbaFormat.substr(4); }

// The bounds of the divisor Σα·w in S_oit. McGuire–Bavoil listing 3 clamps it to [1e-4, 5e4]
// (the default of WBOIT and MBOIT); thesis eq. 2.7 prints the quotient without a clamp, which
// bounds of ±∞ give (none). Unclamped, a divisor of 0 (a pixel no fragment reached, or only
// fragments of α = 0) would make the quotient 0/0 and the pixel NaN; there the average is taken as
// 0, what the clamped divisor gives, so the pixel keeps its background (eq. 2.5's factor
// 1 − Π(1 − α) is 0 there). The weighted average's divisor Σα (wavg) has only the lower bound
// 1e-4 (atLeast).
struct ResolveClamp {
  float low = 1e-4f, high = 5e4f;
  static constexpr ResolveClamp atLeast(float low) { return {low, std::numeric_limits<float>::infinity()}; }
  static constexpr ResolveClamp none() { return {-std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()}; }
  // sum / the clamped divisor; 0 where the divisor is 0.
  glm::vec3 average(const glm::vec3& sum, float divisor) const {
    const float d = std::clamp(divisor, low, high);
    return d == 0.0f ? glm::vec3(0.0f) : sum / d;
  }
};
// WBOIT's and MBOIT's option clamp=mb|none.
inline ResolveClamp resolveClampOption(const MethodOptions& o) {
  return o.text("clamp") == "none" ? ResolveClamp::none() : ResolveClamp{};
}
// S_oit of WBOIT and MBOIT (thesis eq. 2.7; with McGuire–Bavoil listing 3's clamp by default):
// the weighted average accum.rgb / clamp(accum.a, low, high) and, as alpha, the revealage.
inline glm::vec4 weightedResolve(const glm::vec4& accum, float reveal, ResolveClamp clamp = {}) {
  return {clamp.average(glm::vec3(accum), accum.a), reveal};
}
// weightedResolve(accum[i], reveal[i], clamp) for i < n, two fragments at a time in eight vector
// lanes (the same comparisons and divisions lane for lane; a test holds it to weightedResolve).
inline void weightedResolveRow(const glm::vec4* accum, const float* reveal, int n, glm::vec4* out, ResolveClamp clamp = {}) {
  typedef float f8 __attribute__((vector_size(32)));
  const f8 lo = f8{} + clamp.low, hi = f8{} + clamp.high, zero = f8{};
  int i = 0;
  for (; i + 2 <= n; i += 2) {
    f8 a;
    std::memcpy(&a, accum + i, sizeof a);
    const f8 alpha = __builtin_shufflevector(a, a, 3, 3, 3, 3, 7, 7, 7, 7);
    const f8 divisor = alpha < lo ? lo : hi < alpha ? hi : alpha;  // std::clamp's comparisons
    f8 s = divisor == zero ? zero : a / divisor;
    s[3] = reveal[i], s[7] = reveal[i + 1];
    std::memcpy(out + i, &s, sizeof s);
  }
  for (; i < n; ++i) out[i] = weightedResolve(accum[i], reveal[i], clamp);
}


// The accumulation pass of McGuire–Bavoil eq. 6 (listing 3), which WBOIT, MBOIT and MT share:
// accum += (c·α·w, α·w) blended ONE, ONE and reveal *= (1 − α) blended ZERO,
// ONE_MINUS_SRC_COLOR, against the opaque depth; weights(const FragmentBatch& in,
// const glm::vec4* colors, float* w) sets each fragment's w of a batch at once.
Framebuffer weightedAccumulationTargets(FrameTargets& targets, Image& accum, Image& reveal);
PipelineState weightedAccumulationState(const Profile& profile);
template <typename Weights>
void accumulateWeightedBatch(PassRunner& run, FrameTargets& targets, Image& accum, Image& reveal, const Weights& weights) {
  Framebuffer fb = weightedAccumulationTargets(targets, accum, reveal);
  run.transparentBatchPass("accumulate", fb, weightedAccumulationState(run.context().profile),
                           [&weights](const FragmentBatch& in, const glm::vec4* colors, FragmentBatchOutput& out) {
                             float w[kShaderBatch];
                             weights(in, colors, w);
                             for (int i = 0; i < in.count; ++i) {
                               const glm::vec4& c = colors[i];
                               out.write(i, 0, glm::vec4(glm::vec3(c) * c.a * w[i], c.a * w[i]));
                               out.write(i, 1, glm::vec4(c.a));
                             }
                           });
}

// The composite of WBOIT, MBOIT and stochastic transparency: weightedResolve(accum, reveal, clamp)
// blended over the background (PassRunner::blendOverBackground).
void compositeWeighted(PassRunner& run, FrameTargets& targets, const Image& accum, const Image& reveal,
                       ResolveClamp clamp = {});

// Bavoil–Myers's weighted average of n layers accumulated as (Σ c·α, Σ α) (n > 0): the average
// colour Σcα / max(Σα, 1e-4) (the divisor's bounds: `clamp`; ResolveClamp::none() divides by Σα
// as thesis eq. 2.3 prints it) and, as alpha, the transmittance T = max(0, 1 − Σα/n)^n.
inline glm::vec4 weightedAverageResolve(const glm::vec4& accum, float count, ResolveClamp clamp = ResolveClamp::atLeast(1e-4f)) {
  const float meanAlpha = accum.a / count;
  return {clamp.average(glm::vec3(accum), accum.a), powInt(std::max(0.0f, 1.0f - meanAlpha), unsigned(count))};
}

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

}  // namespace oitref::methods
