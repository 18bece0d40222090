// Stochastic transparency (Enderton, Sintorn, Shirley, Luebke, "Stochastic Transparency",
// I3D 2010), with S samples per pixel:
//   1. stochastic depth: every transparent fragment covers a random subset of round(α·S) of the
//      pixel's S samples, and is depth-tested (LESS, with writes) like an opaque surface in
//      each covered sample;
//   2. accumulation: every transparent fragment adds (c·α·v, α·v) (ONE, ONE), v the share of
//      the S samples whose stochastic depth is not in front of it (LEQUAL) — its estimated
//      visibility Π(1 − α_j) over the layers in front; the revealage Π(1 − α) is accumulated
//      exactly beside it (ZERO, ONE_MINUS_SRC_COLOR);
//   3. alpha correction: C = accum.rgb / accum.a · (1 − Π(1 − α)) + C0 · Π(1 − α), the
//      composite of the weighted methods — exact coverage, normalised colour.
// oitref has no multisampling, so the S samples are S depth planes ("sample_depth_s", d24, a GPU's
// MSAA depth buffer), all at the pixel centre: they carry the stochastic masks only, not
// geometric antialiasing. Pass 1 runs once per sample plane with the pipeline's own depth test,
// each run keeping the fragments whose mask has that sample; pass 2 reads the S planes in the
// shader, the visibility that an MSAA resolve would average. The masks are a function of
// (seed, pixel, object, primitive): the same bits on every run and thread count.
#include <algorithm>
#include <cmath>

#include "methods/method_common.h"
#include "methods/methods.h"
#include "util/seeded_random.h"

namespace oitref::methods {

uint64_t stochasticFragmentKey(uint32_t seed, int x, int y, uint32_t object, uint32_t primitive) {
  return (uint64_t(seed) << 32) ^ (uint64_t(uint32_t(x)) << 16) ^ uint64_t(uint32_t(y)) ^ (uint64_t(object) << 40) ^
         (uint64_t(primitive) * 0x2545f4914f6cdd1dull);
}

uint32_t stochasticMask(uint32_t seed, int x, int y, uint32_t object, uint32_t primitive, float alpha, int samples) {
  using util::splitMix64;
  const int bits = std::clamp(int(std::floor(double(alpha) * samples + 0.5)), 0, samples);
  uint64_t state = stochasticFragmentKey(seed, x, y, object, primitive);
  splitMix64(state);
  // The first `bits` entries of a Fisher–Yates shuffle of the sample indices.
  int order[32];
  for (int i = 0; i < samples; ++i) order[i] = i;
  uint32_t mask = 0;
  for (int i = 0; i < bits; ++i) {
    const int j = i + int(splitMix64(state) % uint64_t(samples - i));
    std::swap(order[i], order[j]);
    mask |= 1u << order[i];
  }
  return mask;
}

namespace {

class Stochastic final : public OpaqueFirstMethod {
 public:
  explicit Stochastic(const MethodOptions& o)
      : samples_(o.integer("samples")), seed_(uint32_t(o.number("seed"))) {
    for (int s = 0; s < samples_; ++s)
      sampleDepth_.push_back(declared.depth("sample_depth_" + std::to_string(s), DepthFormat::D24, "stochastic depth of sample " + std::to_string(s)));
    accum_ = declared.color("accum", o.format("accum"), "Σ(c·α·v, α·v), v the share of samples not in front, ONE, ONE");
    reveal_ = declared.color("reveal", singleChannelFormat(o.text("accum")), "Π(1 − α), ZERO, ONE_MINUS_SRC_COLOR");
  }
  const MethodInfo& info() const override { return stochasticInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {
    const int samples = samples_;
    const uint32_t seed = seed_;
    std::vector<DepthBuffer*> sampleDepth;
    PipelineState solid;
    solid.profile = context.profile;
    solid.depth = {true, CompareFunc::Less, true, false};
    for (int s = 0; s < samples; ++s) {
      DepthBuffer& d = t[sampleDepth_[size_t(s)]];
      d = t.depth();  // the opaque surfaces are in every sample
      sampleDepth.push_back(&d);
      Framebuffer fb;
      fb.depth = &d;
      run.transparentPass("stochastic depth " + std::to_string(s), fb, solid,
                          [&, s](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
                            const uint32_t mask = stochasticMask(seed, in.x, in.y, in.drawId,
                                                                 in.primitiveId, c.a, samples);
                            if (!(mask >> s & 1u)) out.discard();
                          },
                          /*mayDiscard=*/true, /*pure=*/true);
    }
    Image& accum = t[accum_];
    Image& reveal = t[reveal_];
    accum.clear(glm::vec4(0.0f), context.profile);
    reveal.clear(glm::vec4(1.0f), context.profile);
    Framebuffer fb;
    fb.color[0] = &accum;
    fb.color[1] = &reveal;
    fb.depth = &t.depth();
    PipelineState st = transparentState(context.profile, additiveBlend());
    st.blend[1] = revealageBlend();
    const DepthFormat format = t.depth().format();
    const TextureFiltering read = context.profile.texture;
    run.transparentPass("accumulate", fb, st, [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
      const uint32_t z = encodeDepth(in.depth, format);
      int visible = 0;
      // The stored depths as the shader fetches them (depthCodeAsFetched: the stored codes, except
      // under llvmpipe's texture unit).
      for (const DepthBuffer* d : sampleDepth) visible += z <= depthCodeAsFetched(d->load(in.x, in.y), format, read);
      const float v = float(visible) / float(samples);
      out.write(0, premultiplied(c, v));
      out.write(1, glm::vec4(c.a));
    });
    compositeWeighted(run, t, accum, reveal);
  }

 private:
  int samples_;
  uint32_t seed_;
  std::vector<DepthHandle> sampleDepth_;
  ColorHandle accum_, reveal_;
};

}  // namespace

const MethodInfo& stochasticInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "stochastic",
      "stochastic transparency (Enderton et al. 2010): random sample masks, depth per sample, alpha correction",
      {{"variant", "enderton", "enderton: Enderton et al.'s stratified masks and weighted accumulation; vallius: Vallius's "
                 "listings 4.3–4.9 as printed (a random test per fragment, S unblended passes, bg·T + c·(1 − T))",
        {"enderton", "vallius"}},
       {"samples", "8", "samples per pixel S (each fragment covers round(α·S) of them); vallius: S passes", {"8", "16", "32"}},
       {"seed", "1", "seed of the coverage masks (vallius: of the per-fragment random values)", {},
        OptionNumber::integer(0, 4294967295.0)},
       {"accum", "rgba16f", "accumulation format (vallius: the samples' target; listing 4.3's RGBA16F); the revealage uses the same encoding in one channel",
        {"rgba16f", "rgba32f"}}}};
    i.studyVariants = {{{"samples", "16"}}, {{"samples", "32"}}, {{"variant", "vallius"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> stochasticFactory(const MethodOptions& o) {
  if (o.is("variant", "vallius")) return stochasticValliusFactory(o);
  return std::make_unique<Stochastic>(o);
}

}  // namespace oitref::methods
