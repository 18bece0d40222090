// Moment transparency (Sharpe 2018): moment-based weights with the choices of Sharpe's moment
// transparency rather than Münstermann et al.'s:
//   depth:    u = ln(v/near) / ln(far/near) ∈ [0, 1], v the view depth
//   pass 1:   A = −ln(1 − min(α, 1 − 0.5/256)); optical depth += A, moments += A·(u, u², u³, u⁴)
//             (both blended ONE, ONE)
//   pass 2:   b = moments / optical depth (when it is not 0), biased by β = 3e-7 towards
//             (0, 0.375, 0, 0.375); the Hamburger four-moment shadow-map bound (MSM: the root
//             weights 1 in front of u and 0 at u, i.e. overestimation 0) clamped to [0, 1];
//             w = exp(−optical depth · bound); accum += (c·α·w, α·w), reveal *= (1 − α)
//   composite: as WBOIT.
// The reconstruction is moment_math.cpp's (the same fp32 closed form as mboit power4).
#include <algorithm>
#include <atomic>

#include "methods/det_math.h"
#include "methods/method_common.h"
#include "methods/methods.h"
#include "methods/moment_math.h"

namespace oitref::methods {
namespace {

class Mt final : public Method {
 public:
  explicit Mt(const MethodOptions& o) : bias_(float(o.number("bias"))), accumFormat_(o.text("accum")) {}
  const MethodInfo& info() const override { return mtInfo(); }
  std::vector<AttachmentDecl> attachments() const override {
    std::vector<AttachmentDecl> a = opaqueAttachments();
    a.push_back(colorAttachment("optical_depth", "r32f", "Σ −ln(1 − α), blended ONE, ONE"));
    a.push_back(colorAttachment("moments", "rgba32f", "Σ −ln(1 − α)·(u, u², u³, u⁴), blended ONE, ONE"));
    a.push_back(colorAttachment("accum", accumFormat_, "Σ(c·α·w, α·w), blended ONE, ONE"));
    a.push_back(colorAttachment("reveal", "r32f", "Π(1 − α), blended ZERO, ONE_MINUS_SRC_COLOR"));
    return a;
  }
  FrameResult render(const FrameContext& context) override {
    FrameResult result;
    FrameTargets t(attachments(), context);
    PassRunner run(context, result);
    run.opaquePass(t);
    const Profile& profile = context.profile;
    Image& opticalDepth = t.color("optical_depth");
    Image& moments = t.color("moments");
    Image& accum = t.color("accum");
    Image& reveal = t.color("reveal");
    opticalDepth.clear(glm::vec4(0.0f), profile);
    moments.clear(glm::vec4(0.0f), profile);
    accum.clear(glm::vec4(0.0f), profile);
    reveal.clear(glm::vec4(1.0f), profile);
    const Camera& cam = context.scene.camera;
    const double logRange = detLog(double(cam.farPlane) / double(cam.nearPlane));
    auto unitDepth = [&](const FragmentInput& in) {
      return float(detLog(double(in.viewDepth) / double(cam.nearPlane)) / logRange);
    };

    Framebuffer momentFb;
    momentFb.color[0] = &opticalDepth;
    momentFb.color[1] = &moments;
    momentFb.depth = &t.depth("depth");
    run.transparentPass("moments", momentFb, transparentState(profile, additiveBlend()),
                        [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
                          const float a = float(-detLog(1.0 - double(std::min(c.a, 1.0f - 0.5f / 256.0f))));
                          const float u = unitDepth(in), u2 = u * u;
                          out.write(0, glm::vec4(a));
                          out.write(1, glm::vec4(u, u2, u2 * u, u2 * u2) * a);
                        });

    const float bias = bias_;
    const float* biasVector = powerBiasVector(4, false);
    std::atomic<uint64_t> fallbacks{0};
    accumulateWeighted(run, t, accum, reveal, [&](const FragmentInput& in, const glm::vec4&) {
      const float total = opticalDepth.fetch(in.x, in.y).r;
      glm::vec4 m = moments.fetch(in.x, in.y);
      if (total != 0.0f) m /= total;
      const float b[4] = {m.x, m.y, m.z, m.w};
      bool fellBack = false;
      const float bound = std::clamp(powerMomentAbsorbance(4, b, unitDepth(in), bias, biasVector, 0.0f, &fellBack), 0.0f, 1.0f);
      if (fellBack) fallbacks.fetch_add(1, std::memory_order_relaxed);
      return float(detExp(-double(bound) * double(total)));
    });

    compositeWeighted(run, t, accum, reveal);
    t.finish(result, "opaque");
    result.facts.emplace_back("moment reconstructions that fell back", std::to_string(fallbacks.load()));
    return result;
  }

 private:
  float bias_;
  std::string accumFormat_;
};

}  // namespace

const MethodInfo& mtInfo() {
  static const MethodInfo info{
      "mt",
      "moment transparency (Sharpe 2018): 4 power moments of the log depth in [0, 1], MSM bound",
      {{"bias", "3e-7", "moment bias β towards (0, 0.375, 0, 0.375)", {}},
       {"accum", "rgba32f", "accumulation format", {"rgba16f", "rgba32f"}}}};
  return info;
}
std::unique_ptr<Method> makeMt(const MethodOptions& o) { return std::make_unique<Mt>(o); }

}  // namespace oitref::methods
