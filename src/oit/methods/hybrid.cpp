// Hybrid transparency (Maule, Comba, Torchelsen, Bastos, "Hybrid Transparency", I3D 2013): the k
// nearest fragments of a pixel (the core) are composited exactly, the rest (the tail) are
// approximated by Bavoil–Myers's weighted average, and the core goes over the tail:
//   C = OVER_{core, front to back}(c_i, α_i) over [ avg·(1 − T) + C0·T ],
//   avg = Σ_tail c·α / Σ_tail α,  T = (1 − Σ_tail α / n_tail)^n_tail.
// One geometry pass builds both, the way a GPU with raster-ordered access (ROVs, pixel sync)
// does it: fragments of a pixel arrive in submission order, each reads the pixel's core — k
// depth slots sorted front to back, then k colour slots — and
//   * goes into the core at its place, the core's last fragment (if the core was full) leaving
//     for the tail, or
//   * goes to the tail itself when it is behind all k.
// Whatever leaves for the tail is the pass's blended output, (c·α, α) into "tail" and 1 into
// "tail_count" (ONE, ONE). A fragment as deep as a core one goes behind it: the earlier
// submission stays in front, the ground truths' tie rule. Core colours are stored straight in
// `core` format (a fragment that is evicted later reaches the tail as stored), depths as the
// fragment's window depth in R32F (cleared to 2, beyond any window depth: empty).
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

constexpr float kEmpty = 2.0f;  // a core depth slot's clear value: behind every window depth

class Hybrid final : public OpaqueFirstMethod {
 public:
  explicit Hybrid(const MethodOptions& o) : k_(o.integer("k")) {
    for (int i = 0; i < k_; ++i)
      coreDepth_.push_back(declared.color("core_depth_" + std::to_string(i), "r32f", "window depth of the core's fragment " + std::to_string(i)));
    for (int i = 0; i < k_; ++i)
      coreColor_.push_back(declared.color("core_color_" + std::to_string(i), o.format("core"), "straight (c, α) of the core's fragment " + std::to_string(i)));
    tail_ = declared.color("tail", o.format("tail"), "Σ(c·α, α) of the tail, blended ONE, ONE");
    tailCount_ = declared.color("tail_count", singleChannelFormat(o.text("tail")), "n of the tail, blended ONE, ONE");
  }
  const MethodInfo& info() const override { return hybridInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {
    const int k = k_;
    std::vector<Image*> depth(static_cast<size_t>(k)), color(static_cast<size_t>(k));
    for (int i = 0; i < k; ++i) {
      depth[size_t(i)] = &t[coreDepth_[size_t(i)]];
      color[size_t(i)] = &t[coreColor_[size_t(i)]];
      depth[size_t(i)]->clear(glm::vec4(kEmpty), context.profile);
      color[size_t(i)]->clear(glm::vec4(0.0f), context.profile);
    }
    Image& tail = t[tail_];
    Image& tailCount = t[tailCount_];
    tail.clear(glm::vec4(0.0f), context.profile);
    tailCount.clear(glm::vec4(0.0f), context.profile);
    Framebuffer fb;
    fb.color[0] = &tail;
    fb.color[1] = &tailCount;
    fb.depth = &t.depth();
    const Profile& profile = context.profile;
    run.transparentPass("core and tail", fb, transparentState(profile, additiveBlend()),
                        [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
                          int place = 0;
                          while (place < k && depth[size_t(place)]->fetch(in.x, in.y).r <= in.depth) ++place;
                          glm::vec4 leaving = c;  // behind the whole core: the fragment itself
                          if (place < k) {
                            const bool full = depth[size_t(k - 1)]->fetch(in.x, in.y).r != kEmpty;
                            leaving = full ? color[size_t(k - 1)]->fetch(in.x, in.y) : glm::vec4(0.0f);
                            for (int i = k - 1; i > place; --i) {
                              depth[size_t(i)]->store(in.x, in.y, depth[size_t(i - 1)]->fetch(in.x, in.y), profile);
                              color[size_t(i)]->store(in.x, in.y, color[size_t(i - 1)]->fetch(in.x, in.y), profile);
                            }
                            depth[size_t(place)]->store(in.x, in.y, glm::vec4(in.depth), profile);
                            color[size_t(place)]->store(in.x, in.y, c, profile);
                            if (!full) {
                              out.write(0, glm::vec4(0.0f));  // nothing leaves; adding zero is exact
                              out.write(1, glm::vec4(0.0f));
                              return;
                            }
                          }
                          out.write(0, glm::vec4(glm::vec3(leaving) * leaving.a, leaving.a));
                          out.write(1, glm::vec4(1.0f));
                        });
    // The core over the tail over the background, in each presented target's own background.
    run.compositeOntoBackgrounds(t, "composite", [&](const FragmentInput& in, const glm::vec3 c0[2], glm::vec3 out[2]) {
      const float n = tailCount.fetch(in.x, in.y).r;
      glm::vec4 tailResolve(0.0f, 0.0f, 0.0f, 1.0f);  // (avg, T): no tail lets the background through
      if (n > 0.0f) tailResolve = weightedAverageResolve(tail.fetch(in.x, in.y), n);
      for (int target = 0; target < 2; ++target) {
        glm::vec3 result = glm::vec3(tailResolve) * (1.0f - tailResolve.a) + c0[target] * tailResolve.a;
        for (int i = k - 1; i >= 0; --i) {
          if (depth[size_t(i)]->fetch(in.x, in.y).r == kEmpty) continue;
          const glm::vec4 s = color[size_t(i)]->fetch(in.x, in.y);
          result = glm::vec3(s) * s.a + result * (1.0f - s.a);
        }
        out[target] = result;
      }
      return true;
    });
  }

 private:
  int k_;
  std::vector<ColorHandle> coreDepth_, coreColor_;
  ColorHandle tail_, tailCount_;
};

}  // namespace

const MethodInfo& hybridInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "hybrid",
      "hybrid transparency (Maule et al. 2013): the k nearest exact, the tail as a weighted average",
      {{"k", "4", "fragments kept exactly per pixel (the core)", {"2", "4", "8", "16"}},
       {"core", "rgba32f", "format of the core's colour slots", {"rgba8", "rgba16f", "rgba32f"}},
       {"tail", "rgba16f", "tail accumulation format; its count uses the same encoding in one channel", {"rgba16f", "rgba32f"}}}};
    i.studyVariants = {{{"k", "2"}}, {{"k", "8"}}, {{"k", "16"}}, {{"core", "rgba8"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> hybridFactory(const MethodOptions& o) { return std::make_unique<Hybrid>(o); }

}  // namespace oitref::methods
