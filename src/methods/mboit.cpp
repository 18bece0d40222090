// Moment-based OIT with 4 power moments (Münstermann, Krumpen, Klein, Peters 2018), in the shape
// of Rožek's thesis Algorithm 6 (eq. 2.8–2.11):
//   pass 1, additive:  b0 += A,  (b1..b4) += A·(z, z², z³, z⁴),  A = −ln(1 − α)
//   pass 2:            w = T(z) = exp(−b0 · absorbance(b/b0, z)), accumulated as WBOIT does:
//                      accum += (c·α·w, α·w), reveal *= (1 − α)
//   composite:         (accum.rgb / clamp(accum.a, 1e-4, 5e4), reveal) over the background
// absorbance (moment reconstruction): b ← (1 − β)·b + β·(0, 0.375, 0, 0.375); solve the Hankel
// system [1 b1 b2; b1 b2 b3; b2 b3 b4]·c = (1, z, z²) by Cholesky; the roots z1, z2 of
// c0 + c1·x + c2·x² and z itself support the reconstructed depth distribution; the quadratic p
// through (z, overestimation), (z1, [z1 < z]), (z2, [z2 < z]) gives absorbance = p0 + p1·b1 + p2·b2.
// Depth z in [−1, 1]: warp=linear uses 2·d − 1 (d the window depth); warp=log uses
// 2·ln(v/near)/ln(far/near) − 1 (v the view depth), so the bias vector fits both.
// Guards: α is clamped to 1 − 2^-20 (α = 1 would make A infinite); fragments with A below
// 1e-7 add no moments; in pass 2 a pixel with b0 < 0.00100050033 (its layers are all nearly
// clear) uses w = 1; a Hankel matrix that is not positive definite (one layer and β = 0) or
// non-finite roots fall back to absorbance = overestimation (the fragment's own layer).
// ln and exp are det_math.h's, so the weights are the same bits on every machine.
#include <algorithm>
#include <atomic>
#include <cmath>

#include "methods/det_math.h"
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {

// The moment reconstruction, in fp32 as a shader would (exposed for the tests).
float mboitAbsorbance(const float b[4], float z, float bias, float overestimation, bool* fellBack) {
  if (fellBack) *fellBack = false;
  auto fallBack = [&] {
    if (fellBack) *fellBack = true;
    return overestimation;
  };
  const float biasVector[4] = {0.0f, 0.375f, 0.0f, 0.375f};
  float m[4];
  for (int i = 0; i < 4; ++i) m[i] = (1.0f - bias) * b[i] + bias * biasVector[i];
  // Cholesky of [1 m0 m1; m0 m1 m2; m1 m2 m3] = L·D·Lᵀ.
  const float d11 = m[1] - m[0] * m[0];
  const float l21d11 = m[2] - m[0] * m[1];
  if (!(d11 > 0.0f)) return fallBack();
  const float l21 = l21d11 / d11;
  const float d22 = (m[3] - m[1] * m[1]) - l21d11 * l21;
  if (!(d22 > 0.0f)) return fallBack();
  // Solve L·D·Lᵀ·c = (1, z, z²).
  float c0 = 1.0f, c1 = z - m[0], c2 = z * z - m[1] - l21 * c1;
  c1 = c1 / d11;
  c2 = c2 / d22;
  c1 = c1 - l21 * c2;
  c0 = c0 - (c1 * m[0] + c2 * m[1]);
  // Roots of c0 + c1·x + c2·x².
  const float p = c1 / c2, q = c0 / c2;
  const float disc = p * p * 0.25f - q;
  const float r = std::sqrt(disc);
  const float z1 = -p * 0.5f - r, z2 = -p * 0.5f + r;
  if (!std::isfinite(z1) || !std::isfinite(z2)) return fallBack();
  // Newton form of the quadratic through (z, f0), (z1, f1), (z2, f2).
  const float f0 = overestimation, f1 = z1 < z ? 1.0f : 0.0f, f2 = z2 < z ? 1.0f : 0.0f;
  const float f01 = (f1 - f0) / (z1 - z);
  const float f12 = (f2 - f1) / (z2 - z1);
  const float f012 = (f12 - f01) / (z2 - z);
  // p(x) = f0 + f01·(x − z) + f012·(x − z)(x − z1) = a0 + a1·x + a2·x².
  const float a2 = f012;
  const float a1 = f01 - f012 * (z + z1);
  const float a0 = f0 - f01 * z + f012 * z * z1;
  const float absorbance = a0 + a1 * m[0] + a2 * m[1];
  return std::isfinite(absorbance) ? absorbance : fallBack();
}

namespace {

class Mboit final : public Method {
 public:
  explicit Mboit(const MethodOptions& o)
      : bias_(float(o.number("bias"))), overestimation_(float(o.number("overestimation"))),
        logWarp_(o.text("warp") == "log"), accumFormat_(o.text("accum")) {}
  const MethodInfo& info() const override { return mboitInfo(); }
  std::vector<AttachmentDecl> attachments() const override {
    std::vector<AttachmentDecl> a = opaqueAttachments();
    a.push_back(colorAttachment("b0", "r32f", "C_Ms: Σ −ln(1 − α), blended ONE, ONE"));
    a.push_back(colorAttachment("moments", "rgba32f", "C_Mq: Σ −ln(1 − α)·(z, z², z³, z⁴), blended ONE, ONE"));
    a.push_back(colorAttachment("accum", accumFormat_, "Σ(c·α·w, α·w), blended ONE, ONE"));
    a.push_back(colorAttachment("reveal", "r32f", "Π(1 − α), blended ZERO, ONE_MINUS_SRC_COLOR"));
    return a;
  }
  FrameResult render(const FrameContext& context) override {
    FrameResult result;
    FrameTargets t(attachments(), context.width, context.height);
    PassRunner run(context, result);
    run.opaquePass(t);
    Image& b0Image = t.color("b0");
    Image& moments = t.color("moments");
    Image& accum = t.color("accum");
    Image& reveal = t.color("reveal");
    b0Image.clear(glm::vec4(0.0f), context.profile);
    moments.clear(glm::vec4(0.0f), context.profile);
    accum.clear(glm::vec4(0.0f), context.profile);
    reveal.clear(glm::vec4(1.0f), context.profile);
    const Camera& cam = context.scene.camera;
    const double logRange = detLog(double(cam.farPlane) / double(cam.nearPlane));
    const bool logWarp = logWarp_;
    auto warp = [&, logWarp](const FragmentInput& in) {
      if (!logWarp) return 2.0f * in.depth - 1.0f;
      return float(2.0 * detLog(double(in.viewDepth) / double(cam.nearPlane)) / logRange - 1.0);
    };
    auto absorbanceOf = [](float alpha) {
      return float(-detLog(1.0 - double(std::min(alpha, 1.0f - 0x1p-20f))));
    };

    const PipelineState additive = transparentState(context.profile, additiveBlend());
    Framebuffer momentFb;
    momentFb.color[0] = &b0Image;
    momentFb.color[1] = &moments;
    momentFb.depth = &t.depth("depth");
    run.transparentPass("moments", momentFb, additive, [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
      const float a = absorbanceOf(c.a);
      if (a < 1e-7f) return;  // nearly clear: adds nothing measurable
      const float z = warp(in), z2 = z * z;
      out.write(0, glm::vec4(a));
      out.write(1, glm::vec4(z, z2, z2 * z, z2 * z2) * a);
    });

    PipelineState st = additive;
    st.blend[1] = revealageBlend();
    Framebuffer fb;
    fb.color[0] = &accum;
    fb.color[1] = &reveal;
    fb.depth = &t.depth("depth");
    const float bias = bias_, overestimation = overestimation_;
    std::atomic<uint64_t> fallbacks{0};  // a sum: the same for any order of the fragments
    run.transparentPass("accumulate", fb, st, [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
      const float b0 = b0Image.fetch(in.x, in.y).r;
      float w = 1.0f;
      if (b0 >= 0.00100050033f) {
        const glm::vec4 m = moments.fetch(in.x, in.y) / b0;
        const float b[4] = {m.x, m.y, m.z, m.w};
        bool fellBack = false;
        const float absorbance = mboitAbsorbance(b, warp(in), bias, overestimation, &fellBack);
        if (fellBack) fallbacks.fetch_add(1, std::memory_order_relaxed);
        w = std::clamp(float(detExp(-double(b0) * double(absorbance))), 0.0f, 1.0f);
      }
      out.write(0, glm::vec4(glm::vec3(c) * c.a * w, c.a * w));
      out.write(1, glm::vec4(c.a));
    });

    compositeWeighted(run, t, accum, reveal);  // as WBOIT
    t.finish(result, "opaque");
    result.facts.emplace_back("moment reconstructions that fell back", std::to_string(fallbacks.load()));
    return result;
  }

 private:
  float bias_, overestimation_;
  bool logWarp_;
  std::string accumFormat_;
};

}  // namespace

const MethodInfo& mboitInfo() {
  static const MethodInfo info{
      "mboit",
      "moment-based OIT, 4 power moments (Münstermann et al. 2018; thesis Algorithms 5–6)",
      {{"bias", "5e-7", "moment bias β towards (0, 0.375, 0, 0.375); the thesis used 0", {}},
       {"overestimation", "0.25", "weight of the fragment's own depth in the absorbance", {}},
       {"warp", "linear", "depth into [−1, 1]: linear 2d − 1 (window depth) or log of the view depth", {"linear", "log"}},
       {"accum", "rgba32f", "accumulation format (thesis: RGBA32F)", {"rgba16f", "rgba32f"}}}};
  return info;
}
std::unique_ptr<Method> makeMboit(const MethodOptions& o) { return std::make_unique<Mboit>(o); }

}  // namespace oitref::methods
