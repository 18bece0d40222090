// Weighted sum (Meshkin 2007), Rožek's thesis Algorithm 2 and eq. 2.1:
//   C = Σ c_i·α_i + C0·(1 − Σ α_i)
// No clamping: the background weight goes negative when Σα > 1, so images darken and leave the
// gamut at high α (thesis §2.2).
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

class Wsum final : public Method {
 public:
  explicit Wsum(const MethodOptions& o)
      : accum_(declared_.color("accum", o.format("accum"), "C2: Σ(c·α, α), blended ONE, ONE")),
        final_(declared_.color("final", "rgba8", "C3: the composite")) {}
  const MethodInfo& info() const override { return wsumInfo(); }
  std::vector<AttachmentDecl> attachments() const override { return declared_.declared(); }
  FrameResult render(const FrameContext& context) override {
    FrameResult result;
    FrameTargets t(attachments(), context);
    PassRunner run(context, result);
    run.opaquePass(t);                                    // steps 1–3
    Image& opaque = t.opaque();
    Image& accum = t[accum_];
    Framebuffer fb;                                       // step 5: D2 ← D1 (the same depth)
    fb.color[0] = &accum;
    fb.clearColor[0] = glm::vec4(0.0f);                   // step 4, by the pass (tile by tile)
    fb.depth = &t.depth();
    const PipelineState st = transparentState(context.profile, additiveBlend());  // steps 6–8
    const bool mayDiscard = false, pure = false, readsDepth = false;  // step 9 reads only the colour
    run.transparentBatchPass("accumulate", fb, st, [](const FragmentBatch& in, const glm::vec4* c, FragmentBatchOutput& out) {
      for (int i = 0; i < in.count; ++i) out.write(i, 0, premultiplied(c[i]));  // step 9: (c·α, α)
    }, mayDiscard, pure, {}, readsDepth);
    // Step 11: C_f = C2.rgb + C1.rgb·(1 − C2.a), a full-screen pass into C3 (and the analysis copy).
    Image& final = t[final_];
    Image& analysis = t.analysis();
    Framebuffer out;
    out.color[0] = &final;
    out.color[1] = &analysis;
    PipelineState plain;
    plain.profile = context.profile;
    run.fullscreenProgram("composite", out, plain, programOfBatch([&](const FragmentBatch& in, FragmentBatchOutput& o) {
      glm::vec4 sumScratch[kShaderBatch], c1[kShaderBatch], c0Scratch[kShaderBatch];
      const glm::vec4* sum = texelsOf(accum, in, sumScratch);
      fetchTexels(opaque, in, c1);
      // The analysis copy is also this pass's target: read in place, before blending writes it.
      const glm::vec4* c0 = texelsOf(analysis, in, c0Scratch);
      for (int i = 0; i < in.count; ++i) {
        const float background = 1.0f - sum[i].a;
        o.writeColor(i, 0, plusScaledOpaque(sum[i], c1[i], background));  // (C2.rgb + C1.rgb·(1 − C2.a), 1)
        o.writeColor(i, 1, plusScaledOpaque(sum[i], c0[i], background));
      }
      o.markWritten(in.count, 0b11u);
    }));
    t.finish(result, final_);
    return result;
  }

 private:
  AttachmentList declared_;
  ColorHandle accum_, final_;
};

}  // namespace

const MethodInfo& wsumInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{"wsum",
                 "weighted sum (Meshkin; thesis Algorithm 2): C = Σc·α + C0·(1 − Σα)",
                 {{"accum", "rgba16f", "accumulation target format (bfloat16 = rgba:e8m7, fp8 = rgba:e5m2)", {"rgba16f", "rgba32f", "rgba:e8m7", "rgba:e5m2"}}},
                 {{"thesis", "Algorithm 2 (the default): C2 RGBA16F, the composite into an RGBA8 C3", {{"accum", "rgba16f"}}}}};
    i.studyVariants = {{{"accum", "rgba32f"}}};
    i.stressVariants = {{{"accum", "rgba16f"}}, {{"accum", "rgba32f"}}, {{"accum", "rgba:e8m7"}}, {{"accum", "rgba:e5m2"}}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> wsumFactory(const MethodOptions& o) { return std::make_unique<Wsum>(o); }

}  // namespace oitref::methods
