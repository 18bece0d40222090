// Screen-door transparency (Akenine-Möller, Haines, Hoffman, Real-Time Rendering, 3rd ed.,
// p. 135; Vallius's thesis §4.4). Transparent surfaces are drawn like opaque ones — depth test
// LESS with depth writes, no blending — but each fragment survives only where its α exceeds its
// pixel's threshold in an N×N ordered (Bayer) dither matrix:
//   threshold(x, y) = (B_N[y mod N][x mod N] + 0.5) / N²,  B_1 = [0],
//   B_2n = [[4·B_n, 4·B_n + 2], [4·B_n + 3, 4·B_n + 1]]
// so α = k/N² covers exactly k pixels of every tile, and a layer's opacity becomes the share of
// the tile it covers. Layers of equal α cover the same pixels, so the nearer hides the farther
// completely — the method's known failure. No attachments beyond the opaque pass's.
#include <cstdint>

#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {

uint32_t bayerIndex(int n, int x, int y) {
  uint32_t b = 0;
  // Built from the coarsest level down: each level adds its 2×2 pattern (0, 2; 3, 1) at weight
  // 4^(levels left).
  for (int size = n; size > 1; size /= 2) {
    const int bx = (x % size) / (size / 2), by = (y % size) / (size / 2);
    const uint32_t quad[2][2] = {{0, 2}, {3, 1}};
    b += quad[by][bx] * uint32_t((n / size) * (n / size));
  }
  return b;
}

namespace {

class Screendoor final : public OpaqueFirstMethod {
 public:
  explicit Screendoor(const MethodOptions& o) : n_(int(o.number("mask"))) {}
  const MethodInfo& info() const override { return screendoorInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {
    Framebuffer fb = t.present(/*withDepth=*/true);
    PipelineState solid;
    solid.profile = context.profile;
    solid.depth = {true, CompareFunc::Less, true, false};
    const int n = n_;
    const float cells = float(n * n);
    run.transparentPass("screen door", fb, solid,
                        [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
                          const float threshold = (float(bayerIndex(n, in.x, in.y)) + 0.5f) / cells;
                          if (!(c.a > threshold)) return out.discard();
                          out.write(0, glm::vec4(glm::vec3(c), 1.0f));
                          out.write(1, glm::vec4(glm::vec3(c), 1.0f));
                        },
                        /*mayDiscard=*/true, /*pure=*/true);
  }

 private:
  int n_;
};

}  // namespace

const MethodInfo& screendoorInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{"screendoor",
                 "screen-door transparency: opaque where α exceeds an ordered dither threshold (Vallius §4.4)",
                 {{"mask", "4", "side of the Bayer dither matrix (α resolves in steps of 1/mask²)", {"2", "4", "8"}}}};
    i.studyVariants = {{{"mask", "8"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> screendoorFactory(const MethodOptions& o) { return std::make_unique<Screendoor>(o); }

}  // namespace oitref::methods
