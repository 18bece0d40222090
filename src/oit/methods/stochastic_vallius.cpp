// Stochastic transparency as Vallius's thesis prints it (listings 4.3–4.9; stochastic
// variant=vallius), beside Enderton et al.'s masks (stochastic.cpp):
//   1. the opaque scene, as every method draws it;
//   2. "total": R16F (listing 4.4, the accumulation's encoding in one channel here) cleared to 1,
//      every transparent fragment writes (α, 0, 0, 0) blended ZERO, ONE_MINUS_SRC_COLOR
//      (listings 4.5–4.6): Π(1 − α), eq. 4.6;
//   3. "samples": cleared to 0 once, then S passes with blending off, each after clearing its own
//      depth buffer: a fragment is discarded when its random value exceeds α (listing 4.8), the
//      nearest survivor writes (c.rgb, 1) (listing 4.7);
//   4. the composite, blending off (listing 4.9): background·T + samples.rgb·(1 − T).
// As printed, and unlike Enderton et al.:
//   * the passes do not average: without blending each overwrites the last, so a pixel keeps the
//     nearest survivor of the last pass that had one (expected value: the sorted composite with
//     its layers' share scaled by 1 − T^S);
//   * neither framebuffer has the opaque depth (totalAlpha has no depth buffer, the samples' own
//     is cleared before each pass), so opaque surfaces do not hide transparent ones behind them.
// The listing's generator reads noperspective coordinates that its vertex shader (not printed)
// sets, through the driver's fp32 cos; oitref draws each fragment's value from SplitMix64 of
// (seed, pixel, sample, object, primitive), 24 bits in [0, 1): the same bits on every run.
#include <cstdint>
#include <string>

#include "methods/method_common.h"
#include "methods/methods.h"
#include "util/seeded_random.h"

namespace oitref::methods {
namespace {

// The fragment's value in pass `sample`: 24 bits of SplitMix64 of its key, in [0, 1).
float valliusRandom(uint32_t seed, int x, int y, int sample, uint32_t object, uint32_t primitive) {
  uint64_t state = stochasticFragmentKey(seed, x, y, object, primitive) ^ uint64_t(sample) << 56;
  return float(util::splitMix64(state) >> 40) * 0x1p-24f;
}

class StochasticVallius final : public OpaqueFirstMethod {
 public:
  explicit StochasticVallius(const MethodOptions& o)
      : samples_(o.integer("samples")), seed_(uint32_t(o.number("seed"))),
        total_(declared.color("total", singleChannelFormat(o.text("accum")), "totalAlpha: Π(1 − α), ZERO, ONE_MINUS_SRC_COLOR")),
        samplesImage_(declared.color("samples", o.format("accum"), "transparentObjects: the last pass's nearest surviving fragment")),
        sampleDepth_(declared.depth("sample_depth", DepthFormat::D24, "transparentObjects' own depth, cleared before each pass")) {}
  const MethodInfo& info() const override { return stochasticInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {  // after step 1, the opaque pass
    Image& total = t[total_];
    Image& samples = t[samplesImage_];
    DepthBuffer& sampleDepth = t[sampleDepth_];
    total.clear(glm::vec4(1.0f, 0.0f, 0.0f, 0.0f), context.profile);                // step 2
    Framebuffer totalFb;
    totalFb.color[0] = &total;
    PipelineState totalState;  // no depth buffer, so no depth test
    totalState.profile = context.profile;
    totalState.blend[0] = revealageBlend();
    run.transparentPass("total", totalFb, totalState, [](const FragmentInput&, const glm::vec4& c, FragmentOutput& out) {
      out.write(0, glm::vec4(c.a, 0.0f, 0.0f, 0.0f));
    });
    samples.clear(glm::vec4(0.0f), context.profile);                                  // step 3
    Framebuffer sampleFb;
    sampleFb.color[0] = &samples;
    sampleFb.depth = &sampleDepth;
    PipelineState solid;  // GL's defaults: LESS with writes, blending off
    solid.profile = context.profile;
    solid.depth = {true, CompareFunc::Less, true, false};
    const uint32_t seed = seed_;
    for (int s = 0; s < samples_; ++s) {
      sampleDepth.clear(1.0);
      run.transparentPass("sample " + std::to_string(s), sampleFb, solid,
                          [seed, s](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
                            if (valliusRandom(seed, in.x, in.y, s, in.drawId, in.primitiveId) > c.a) return out.discard();
                            out.write(0, glm::vec4(glm::vec3(c), 1.0f));
                          },
                          /*mayDiscard=*/true);
    }
    run.compositeOntoBackgrounds(t, "combine", [&](const FragmentInput& in, const glm::vec3 background[2], glm::vec3 out[2]) {
      const float alphaCorrection = total.fetch(in.x, in.y).r;                        // step 4
      const glm::vec3 transparent(samples.fetch(in.x, in.y));
      for (int k = 0; k < 2; ++k) out[k] = background[k] * alphaCorrection + transparent * (1.0f - alphaCorrection);
      return true;
    });
  }

 private:
  int samples_;
  uint32_t seed_;
  ColorHandle total_, samplesImage_;
  DepthHandle sampleDepth_;
};

}  // namespace

std::unique_ptr<Method> stochasticValliusFactory(const MethodOptions& o) { return std::make_unique<StochasticVallius>(o); }

}  // namespace oitref::methods
