// Weighted average (Bavoil–Myers 2008), Rožek's thesis Algorithm 3 and eq. 2.2–2.4:
//   accumulate (c·α, α) and a count n;  avg = Σcα / Σα
//   Bavoil–Myers (default):     C = avg·(1 − T) + C0·T,  T = max(0, 1 − Σα/n)^n
//   thesis eq. 2.2 as printed:  C = avg·(1 − (Σα/n)^n) + C0·(Σα/n)^n
// The printed equation (and S_oit, eq. 2.3) weights the background by the mean alpha instead of
// one minus it: one layer of α = 0.9 would show 90 % background, and α = 0 fragments (particle
// corners) turn black. The thesis's own figures show the published behaviour, so that is the
// default; transmittance=thesis_eq2.2 evaluates the equation as printed.
// n = 0: the background. Σα is divided as max(Σα, 1e-4) (clamp=max), or as it is (clamp=none:
// eq. 2.3 as printed, with 0 where Σα is 0: ResolveClamp::average).
#include <algorithm>

#include "methods/method_common.h"
#include "methods/methods.h"
#include "methods/power.h"

namespace oitref::methods {
namespace {

class Wavg final : public OpaqueFirstMethod {
 public:
  explicit Wavg(const MethodOptions& o)
      : accum_(declared.color("accum", o.format("accum"), "C2q: Σ(c·α, α), blended ONE, ONE")),
        count_(declared.color("count", singleChannelFormat(o.text("accum")), "C2s: n, blended ONE, ONE")),
        thesis_(o.is("transmittance", "thesis_eq2.2")),
        clamp_(o.is("clamp", "none") ? ResolveClamp::none() : ResolveClamp::atLeast(1e-4f)) {}
  const MethodInfo& info() const override { return wavgInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {  // after steps 1–3, the opaque pass
    Image& accum = t[accum_];
    Image& count = t[count_];
    accum.clear(glm::vec4(0.0f), context.profile);                  // step 4
    count.clear(glm::vec4(0.0f), context.profile);                  // step 5
    Framebuffer fb;
    fb.color[0] = &accum;
    fb.color[1] = &count;
    fb.depth = &t.depth();                                          // step 6
    const PipelineState st = transparentState(context.profile, additiveBlend());  // steps 7–8
    run.transparentPass("accumulate", fb, st, [](const FragmentInput&, const glm::vec4& c, FragmentOutput& out) {
      out.write(0, premultiplied(c));             // step 9: S_accum
      out.write(1, glm::vec4(1.0f));
    });
    // Steps 10–11: blend (avg, T) into C1 with C_f = C_s·(1 − α_s) + C_d·α_s.
    const bool thesis = thesis_;
    const ResolveClamp clamp = clamp_;
    run.blendOverBackground(t, [&, thesis, clamp](const FragmentInput& in, glm::vec4& s) {
      const float n = count.fetch(in.x, in.y).r;
      if (n == 0.0f) return false;  // no transparent layer: the background stays
      const glm::vec4 a = accum.fetch(in.x, in.y);
      s = weightedAverageResolve(a, n, clamp);
      if (thesis) s.a = powInt(a.a / n, unsigned(n));  // eq. 2.2 as printed: (Σα/n)^n
      return true;
    });
  }

 private:
  ColorHandle accum_, count_;
  bool thesis_;
  ResolveClamp clamp_;
};

}  // namespace

const MethodInfo& wavgInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "wavg",
      "weighted average (Bavoil–Myers; thesis Algorithm 3, eq. 2.2)",
      {{"accum", "rgba16f",
        "accumulation format (bfloat16 = rgba:e8m7, fp8 = rgba:e5m2); the count uses the same encoding in one channel",
        {"rgba16f", "rgba32f", "rgba:e8m7", "rgba:e5m2"}},
       {"transmittance", "bavoil_myers",
        "background weight: (1 − Σα/n)^n as published (and as the thesis's figures show), or (Σα/n)^n as "
        "the thesis's eq. 2.2 prints it",
        {"bavoil_myers", "thesis_eq2.2"}},
       {"clamp", "max", "the average's divisor: max(Σα, 1e-4), or Σα itself as eq. 2.3 prints it (none)", {"max", "none"}}},
      {{"thesis", "Algorithm 3 as printed: C2q RGBA32F and C2s R32F (the thesis also ran 16F), eq. 2.2–2.3's transmittance and quotient",
        {{"accum", "rgba32f"}, {"transmittance", "thesis_eq2.2"}, {"clamp", "none"}}}}};
    i.studyVariants = {{{"accum", "rgba32f"}}, {{"preset", "thesis"}}};
    i.stressVariants = {{{"accum", "rgba16f"}}, {{"accum", "rgba32f"}}, {{"accum", "rgba:e8m7"}}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> wavgFactory(const MethodOptions& o) { return std::make_unique<Wavg>(o); }

}  // namespace oitref::methods
