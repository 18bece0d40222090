// Meshkin's three-target sort-independent alpha blending (Meshkin, "Sort-Independent Alpha
// Blending", GDC 2007), as Vallius's thesis gives it in listing 4.1:
//   pass 1, blended ONE, ONE:         t1 += (c·α, α),  t2 += (1/α, 1/α, 1/α, α)
//   pass 2, blended ZERO, SRC_COLOR:  t3 *= (c, α)
//   composite, blending off:          out = t1.rgb − bg·t1.a + bg·t3.a + bg·t2.rgb·t3.a
// The listing writes `t1.a = src.rgb`; a three-vector cannot go into one channel, and every
// other use of t1.a in the composite is the background's Σα term (as in the weighted sum), so
// this reads it as src.a. Everything else is as printed. Targets are RGBA16F, the 64-bit format
// Meshkin recommends (`format=rgba32f` to leave fp16 out).
// What the listing computes, in closed form over a pixel's layers (checked by the tests):
//   out = Σ α_i·c_i + bg·(Π α_i·(1 + Σ 1/α_i) − Σ α_i)   (empty product 1, empty sums 0)
// i.e. no layers give bg, one layer αc + bg (OVER gives αc + (1 − α)·bg), two layers
// Σαc + α1α2·bg. It does not reduce to OVER even for one layer: the published pseudocode is
// inconsistent, and this method reproduces it as published rather than guessing a repair.
// McGuire and Bavoil call Meshkin's weighted sum (`wsum`) the higher-quality of his two operators.
// An α of 0 makes 1/α infinite: t2 holds inf and the composite NaN where t3.a is 0, as on a GPU.
#include "blend/method_blend_states.h"
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

class Meshkin3 final : public OpaqueFirstMethod {
 public:
  explicit Meshkin3(const MethodOptions& o)
      : t1_(declared.color("t1", o.format("format"), "Σ(c·α, α), blended ONE, ONE")),
        t2_(declared.color("t2", o.format("format"), "Σ(1/α, 1/α, 1/α, α), blended ONE, ONE")),
        t3_(declared.color("t3", o.format("format"), "Π(c, α), blended ZERO, SRC_COLOR")) {}
  const MethodInfo& info() const override { return meshkin3Info(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {
    const Profile& profile = context.profile;
    Image& t1 = t[t1_];
    Image& t2 = t[t2_];
    Image& t3 = t[t3_];
    t1.clear(glm::vec4(0.0f), profile);
    t2.clear(glm::vec4(0.0f), profile);
    t3.clear(glm::vec4(1.0f), profile);

    Framebuffer sums;
    sums.color[0] = &t1;
    sums.color[1] = &t2;
    sums.depth = &t.depth();
    run.transparentPass("sums", sums, transparentState(profile, additiveBlend()),
                        [](const FragmentInput&, const glm::vec4& c, FragmentOutput& out) {
                          out.write(0, premultiplied(c));
                          out.write(1, glm::vec4(glm::vec3(1.0f / c.a), c.a));
                        });
    Framebuffer product;
    product.color[0] = &t3;
    product.depth = &t.depth();
    run.transparentPass("product", product,
                        transparentState(profile, detail::states::kProduct),
                        [](const FragmentInput&, const glm::vec4& c, FragmentOutput& out) { out.write(0, c); });

    run.compositeOntoBackgrounds(t, "composite", [&](const FragmentInput& in, const glm::vec3 bg[2], glm::vec3 out[2]) {
      const glm::vec4 s1 = t1.fetch(in.x, in.y), s2 = t2.fetch(in.x, in.y), s3 = t3.fetch(in.x, in.y);
      for (int k = 0; k < 2; ++k)
        out[k] = glm::vec3(s1) - bg[k] * s1.a + bg[k] * s3.a + bg[k] * glm::vec3(s2) * s3.a;
      return true;
    });
  }

 private:
  ColorHandle t1_, t2_, t3_;
};

}  // namespace

const MethodInfo& meshkin3Info() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "meshkin3",
      "Meshkin's three-target sort-independent alpha blending, as Vallius's listing 4.1 prints it (GDC 2007)",
      {{"format", "rgba16f", "format of t1, t2, t3 (Meshkin: 64-bit RGBA)", {"rgba16f", "rgba32f"}}},
      {},
      "NaN where a fragment has α = 0 (1/α is inf in t2 and Π α is 0 in t3: inf·0 in the composite), as the "
      "particles' corners outside their disc; inf where Σ 1/α exceeds the format (α < 1/65520 in RGBA16F)"};
    i.studyVariants = {{{"format", "rgba32f"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> meshkin3Factory(const MethodOptions& o) { return std::make_unique<Meshkin3>(o); }

}  // namespace oitref::methods
