// Deep and Fast Approximate OIT (Tsopouridis, Vasilakis, Fudos): one geometry pass extracts
// per-pixel features, a full-screen pass feeds them to a small trained network
// (dfaoit_network.h) that predicts the colour the transparent layers add, and the background
// term is added exactly:
//   C = MLP(x) + C0·Π(1 − α)      (eq. 9),   exact for n ≤ 2: C = g + C0·Π(1 − α).
// The feature pass (the paper's four textures, §4):
//   near_depth_0/1, near_color_0/1   the two nearest fragments, kept by raster-ordered
//                                    read-modify-write (the paper's interlocks), straight (c, α)
//   accum    Σ(c, α)                 ONE, ONE
//   premult  (Σ α·c, Π(1 − α))       RGB ONE, ONE; alpha ZERO, ONE_MINUS_SRC_ALPHA
//   count    n                       ONE, ONE
// and the inference pass subtracts the two nearest from the sums to get the other n − 2.
// The weights are trained by `oitref train-dfaoit` (src/apps/tools/dfaoit_training.cpp) on scenes
// of its own, not the built-in ones, and kept in src/oit/methods/dfaoit_weights.h.
#include "methods/dfaoit_network.h"
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

constexpr float kEmptySlot = 2.0f;  // a near-depth slot's clear value: behind every window depth

class Dfaoit final : public OpaqueFirstMethod {
 public:
  explicit Dfaoit(const MethodOptions& o)
      : nearDepth_{declared.color("near_depth_0", "r32f", "window depth of the nearest fragment"),
                   declared.color("near_depth_1", "r32f", "window depth of the second nearest")},
        nearColor_{declared.color("near_color_0", o.format("accum"), "straight (c, α) of the nearest fragment"),
                   declared.color("near_color_1", o.format("accum"), "straight (c, α) of the second nearest")},
        accum_(declared.color("accum", o.format("accum"), "Σ(c, α), ONE, ONE")),
        premult_(declared.color("premult", o.format("accum"), "(Σ α·c, Π(1 − α)): RGB ONE, ONE; alpha ZERO, ONE_MINUS_SRC_ALPHA")),
        count_(declared.color("count", "r32f", "n, ONE, ONE")) {}
  const MethodInfo& info() const override { return dfaoitInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {
    const Profile& profile = context.profile;
    Image* depth[2] = {&t[nearDepth_[0]], &t[nearDepth_[1]]};
    Image* color[2] = {&t[nearColor_[0]], &t[nearColor_[1]]};
    Image& accum = t[accum_];
    Image& premult = t[premult_];
    Image& count = t[count_];
    for (int i = 0; i < 2; ++i) depth[i]->clear(glm::vec4(kEmptySlot), profile), color[i]->clear(glm::vec4(0.0f), profile);
    accum.clear(glm::vec4(0.0f), profile);
    premult.clear({0, 0, 0, 1}, profile);
    count.clear(glm::vec4(0.0f), profile);
    Framebuffer fb;
    fb.color[0] = &accum;
    fb.color[1] = &premult;
    fb.color[2] = &count;
    fb.depth = &t.depth();
    PipelineState st = transparentState(profile, additiveBlend());
    st.blend[1] = singleTargetWeightedBlend();
    st.blend[2] = additiveBlend();
    run.transparentPass("features", fb, st, [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
      // The two nearest: behind equal depths, the earlier submission stays in front.
      const float d0 = depth[0]->fetch(in.x, in.y).r, d1 = depth[1]->fetch(in.x, in.y).r;
      if (in.depth < d0) {
        depth[1]->store(in.x, in.y, glm::vec4(d0), profile);
        color[1]->store(in.x, in.y, color[0]->fetch(in.x, in.y), profile);
        depth[0]->store(in.x, in.y, glm::vec4(in.depth), profile);
        color[0]->store(in.x, in.y, c, profile);
      } else if (in.depth < d1) {
        depth[1]->store(in.x, in.y, glm::vec4(in.depth), profile);
        color[1]->store(in.x, in.y, c, profile);
      }
      out.write(0, c);
      out.write(1, premultiplied(c));
      out.write(2, glm::vec4(1.0f));
    });
    const DfaoitParameters& network = dfaoitTrainedParameters();
    run.compositeOntoBackgrounds(t, "inference", [&](const FragmentInput& in, const glm::vec3 c0[2], glm::vec3 out[2]) {
      const float n = count.fetch(in.x, in.y).r;
      if (n == 0.0f) return false;  // no transparent layer: the background stays
      const glm::vec4 c1 = color[0]->fetch(in.x, in.y);
      const glm::vec4 c2 = n >= 2.0f ? color[1]->fetch(in.x, in.y) : glm::vec4(0.0f);
      const glm::vec3 g = glm::vec3(c1) * c1.a + glm::vec3(c2) * ((1.0f - c1.a) * c2.a);
      const glm::vec4 p = premult.fetch(in.x, in.y);
      glm::vec3 transparent = g;  // n ≤ 2: exact
      if (n > 2.0f) {
        const glm::vec4 sum = accum.fetch(in.x, in.y);
        float x[kDfaoitInputs];
        dfaoitFeatures(g, glm::vec3(sum) - glm::vec3(c1) - glm::vec3(c2), sum.a - c1.a - c2.a, n, glm::vec3(p), x);
        transparent = dfaoitEvaluate(network, x);
      }
      for (int target = 0; target < 2; ++target) out[target] = transparent + c0[target] * p.a;
      return true;
    });
  }

 private:
  ColorHandle nearDepth_[2], nearColor_[2], accum_, premult_, count_;
};

}  // namespace

const MethodInfo& dfaoitInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "dfaoit",
      "deep and fast approximate OIT (Tsopouridis et al.): features of one pass, a trained 10-32-16-3 network",
      {{"accum", "rgba16f", "format of the feature targets (the paper: 16 bits per value)", {"rgba16f", "rgba32f"}}}};
    i.studyVariants = {{{"accum", "rgba32f"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> dfaoitFactory(const MethodOptions& o) { return std::make_unique<Dfaoit>(o); }

}  // namespace oitref::methods
