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
// ln and exp are det_math.h's (the same bits on every machine); under math=llvmpipe they are the
// driver's fp32 builtins in the GLSL's fp32 expressions (src/apps/glcheck/gl_methods.cpp, mt),
// as mboit does.
#include <algorithm>

#include "methods/det_math.h"
#include "methods/method_common.h"
#include "methods/methods.h"
#include "methods/moment_math.h"
#include "methods/spread_count.h"
#include "oitref/core/shader_builtins.h"

namespace oitref::methods {
namespace {

class Mt final : public OpaqueFirstMethod {
 public:
  explicit Mt(const MethodOptions& o)
      : bias_(float(o.number("bias"))),
        opticalDepth_(declared.color("optical_depth", "r32f", "Σ −ln(1 − α), blended ONE, ONE")),
        moments_(declared.color("moments", "rgba32f", "Σ −ln(1 − α)·(u, u², u³, u⁴), blended ONE, ONE")),
        accum_(declared.color("accum", o.format("accum"), "Σ(c·α·w, α·w), blended ONE, ONE")),
        reveal_(declared.color("reveal", "r32f", "Π(1 − α), blended ZERO, ONE_MINUS_SRC_COLOR")) {}
  const MethodInfo& info() const override { return mtInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& result) override {
    const Profile& profile = context.profile;
    Image& opticalDepth = t[opticalDepth_];
    Image& moments = t[moments_];
    Image& accum = t[accum_];
    Image& reveal = t[reveal_];
    opticalDepth.clear(glm::vec4(0.0f), profile);
    moments.clear(glm::vec4(0.0f), profile);
    // accum and reveal: cleared by their pass (accumulateWeightedBatch).
    const Camera& cam = context.scene.camera;
    const double logRange = detLog(double(cam.farPlane) / double(cam.nearPlane));
    const bool driverMath = profile.math == ShaderMath::Llvmpipe, fused = profile.fma;
    const float logRangeFloat = float(logRange);  // the GLSL's LOG_RANGE
    // The fragments' depths in [0, 1]: ln(view depth / near) / ln(far / near), a batch's
    // logarithms together (detLogBatch: the same bits as detLog).
    auto unitDepths = [&](const FragmentBatch& in, float* u) {
      const int count = in.count;
      if (count <= 0) return;  // never: it tells the compiler that x below is set
      if (driverMath) {  // log(viewDepth() / NEAR) / LOG_RANGE
        for (int i = 0; i < count; ++i) u[i] = llvmpipe::log(in.viewDepth[i] / cam.nearPlane, fused) / logRangeFloat;
        return;
      }
      double x[kShaderBatch], ln[kShaderBatch];
      for (int i = 0; i < count; ++i) x[i] = double(in.viewDepth[i]) / double(cam.nearPlane);
      detLogBatch(x, ln, count);
      for (int i = 0; i < count; ++i) u[i] = float(ln[i] / logRange);
    };

    Framebuffer momentFb;
    momentFb.color[0] = &opticalDepth;
    momentFb.color[1] = &moments;
    momentFb.depth = &t.depth();
    // The optical depths float(−ln(1 − α)) of a batch together (detLogFloatBatch: float(detLog)
    // for each; float(−v) is −float(v)).
    run.transparentBatchPass("moments", momentFb, transparentState(profile, additiveBlend()),
                             [&](const FragmentBatch& in, const glm::vec4* c, FragmentBatchOutput& out) {
                               const int count = in.count;
                               if (count <= 0) return;  // never (FragmentBatch); said so, GCC sees x written
                               float ln[kShaderBatch], depth[kShaderBatch];
                               if (driverMath) {  // log(1.0 − min(c.a, ALPHA_MAX))
                                 float x[kShaderBatch];
                                 for (int i = 0; i < count; ++i) x[i] = 1.0f - std::min(c[i].a, 1.0f - 0.5f / 256.0f);
                                 llvmpipe::logBatch(x, ln, count, fused);
                               } else {
                                 double x[kShaderBatch];
                                 for (int i = 0; i < count; ++i) x[i] = 1.0 - double(std::min(c[i].a, 1.0f - 0.5f / 256.0f));
                                 detLogFloatBatch(x, ln, count);
                               }
                               unitDepths(in, depth);
                               for (int i = 0; i < count; ++i) {
                                 const float a = -ln[i];
                                 const float u = depth[i], u2 = u * u;
                                 out.write(i, 0, glm::vec4(a));
                                 out.write(i, 1, glm::vec4(u, u2, u2 * u, u2 * u2) * a);
                               }
                             });

    const float bias = bias_;
    const float* biasVector = powerBiasVector(4, false);
    SpreadCount fallbacks;
    // A batch at a time: the bounds in lanes (powerMomentAbsorbanceBatch) and the weights'
    // exponentials together (detExpFloatBatch), each the same bits as one fragment at a time.
    accumulateWeightedBatch(run, t, accum, reveal, [&](const FragmentBatch& in, const glm::vec4*, float* w) {
      const int count = in.count;
      if (count <= 0) return;  // never empty (FragmentBatch); said so, GCC sees b and u always written
      float b[4 * kShaderBatch], u[kShaderBatch], total[kShaderBatch], absorbance[kShaderBatch];
      bool fellBack[kShaderBatch];
      double exponent[kShaderBatch];
      for (int i = 0; i < count; ++i) {
        total[i] = opticalDepth.fetch(in.x[i], in.y).r;
        glm::vec4 m = moments.fetch(in.x[i], in.y);
        if (total[i] != 0.0f) m /= total[i];
        for (int k = 0; k < 4; ++k) b[4 * i + k] = m[k];
      }
      unitDepths(in, u);
      powerMomentAbsorbanceBatch(4, b, u, count, bias, biasVector, 0.0f, absorbance, fellBack);
      uint64_t fell = 0;
      for (int i = 0; i < count; ++i) fell += fellBack[i];
      if (fell) fallbacks.add(fell);
      if (driverMath) {  // exp(−clamp(absorbance, 0, 1) · optical depth)
        float x[kShaderBatch];
        for (int i = 0; i < count; ++i) x[i] = -std::clamp(absorbance[i], 0.0f, 1.0f) * total[i];
        llvmpipe::expBatch(x, w, count, fused);
        return;
      }
      for (int i = 0; i < count; ++i) exponent[i] = -double(std::clamp(absorbance[i], 0.0f, 1.0f)) * double(total[i]);
      detExpFloatBatch(exponent, w, count);
    });

    compositeWeighted(run, t, accum, reveal);
    result.stats.momentFallbacks = fallbacks.total();
  }

 private:
  float bias_;
  ColorHandle opticalDepth_, moments_, accum_, reveal_;
};

}  // namespace

const MethodInfo& mtInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "mt",
      "moment transparency (Sharpe 2018): 4 power moments of the log depth in [0, 1], MSM bound",
      {{"bias", "3e-7", "moment bias β towards (0, 0.375, 0, 0.375)", {}, OptionNumber::real(0, 1)},
       {"accum", "rgba32f", "accumulation format", {"rgba16f", "rgba32f"}}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> mtFactory(const MethodOptions& o) { return std::make_unique<Mt>(o); }

}  // namespace oitref::methods
