// "clamped_sum": Meshkin's weighted sum with the background's weight clamped at zero,
//   C = Σ c·α + C0·max(0, 1 − Σα),
// so that where the layers' alphas sum past 1 the background drops out instead of being
// subtracted (the weighted sum, oitref's `wsum`, darkens there). Order-independent: one additive
// pass into an accumulation target, one full-screen composite.
//
// Everything here is oitref's public API: the method's description (options, the variants its
// study should render), its attachments declared once as typed handles, its passes through the
// PassRunner, and its registration.
#include "clamped_sum.h"

#include <algorithm>
#include <memory>

#include <oitref/oit/method_kit.h>

namespace custom {
namespace {

using namespace oitref;

const MethodInfo& clampedSumInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{"clamped_sum",
                 "weighted sum with the background weight clamped at 0: C = Σc·α + C0·max(0, 1 − Σα) (an example)",
                 {{"accum", "rgba16f", "accumulation target format", {"rgba16f", "rgba32f"}}}};
    i.studyVariants = {{{"accum", "rgba32f"}}};  // a row of `oitref study` beside the defaults
    i.stressVariants = {{}};                     // the stability atlas runs the defaults
    return i;
  }();
  return info;
}

class ClampedSum final : public OpaqueFirstMethod {
 public:
  // The opaque pass's "opaque" and "depth" are declared by the base; this method adds one target.
  explicit ClampedSum(const MethodOptions& o)
      : accum_(declared.color("accum", o.format("accum"), "Σ(c·α, α), blended ONE, ONE")) {}
  const MethodInfo& info() const override { return clampedSumInfo(); }

 protected:
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult&) override {
    Image& accum = t[accum_];
    accum.clear(glm::vec4(0.0f), context.profile);
    Framebuffer fb;
    fb.color[0] = &accum;
    fb.depth = &t.depth();  // tested against the opaque surfaces, not written
    run.transparentBatchPass("accumulate", fb, transparentState(context.profile, additiveBlend()),
                             [](const FragmentBatch& in, const glm::vec4* c, FragmentBatchOutput& out) {
                               for (int i = 0; i < in.count; ++i) out.write(i, 0, glm::vec4(glm::vec3(c[i]) * c[i].a, c[i].a));
                             });
    run.compositeOntoBackgrounds(t, "composite", [&accum](const FragmentInput& in, const glm::vec3 background[2], glm::vec3 result[2]) {
      const glm::vec4 sum = accum.fetch(in.x, in.y);
      const float weight = std::max(0.0f, 1.0f - sum.a);
      for (int k = 0; k < 2; ++k) result[k] = glm::vec3(sum) + background[k] * weight;
      return true;
    });
  }

 private:
  ColorHandle accum_;
};

}  // namespace

void registerClampedSum() {
  registerMethod(clampedSumInfo(), [](const MethodOptions& o) { return std::make_unique<ClampedSum>(o); });
}

}  // namespace custom
