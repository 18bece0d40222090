// Dual depth peeling (Bavoil & Myers, "Order Independent Transparency with Dual Depth Peeling",
// NVIDIA 2008): each pass peels the nearest and the farthest unpeeled layer of every pixel at
// once, so N layers take ⌈N/2⌉ peeling passes plus the initial one.
//   init:  depth = MAX over fragments of (−z, z)                       RG32F, MAX blending
//   pass:  with (−near, far) from the previous depth target, each fragment
//            z < near or z > far  (peeled already):  depth ← (−1, −1)
//            near < z < far       (still inside):    depth ← (−z, z)  for the next pass
//            z = near:  front ← front + (c·α·(1 − front.a), …), front.a ← 1 − (1 − front.a)(1 − α)
//            z = far:   back ← (c, α)
//          every target blended with MAX, so the targets' "pass-through" values (the previous
//          front, −1 depths, 0 back) lose to any real write;
//   then:  the back layer OVER the background (back to front), discarding where nothing was
//          peeled; a pass whose back pass draws nothing ends the loop (the sample's occlusion
//          query), or `passes` is reached;
//   final: C = front.rgb + C_background·(1 − front.a).
// The sample's shader writes every output of every fragment and relies on MAX to ignore the
// values that change nothing. `outputs=changing` (the default) leaves those writes out, with the
// same bits (PeelingPassWrites; the test "dualpeel: outputs=changing …" holds it to outputs=all).
// Two fragments at exactly the same depth collide under MAX: at the front, the component-wise
// maximum of their two accumulations wins — a colour neither order would give; at the back, the
// maximum of the two colours. This is the method's documented weakness, and oitref keeps it.
#include "methods/method_common.h"
#include "blend/method_blend_states.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

BlendState maxBlend() { return detail::states::kMax; }

// Which of the sample's writes a peeling pass keeps. All of them (outputs=all), or only those
// that can change a target (outputs=changing), which leaves every target with the same bits:
//  - range ← (−1, −1) for a fragment outside the unpeeled range or on its bounds: the range target
//    only ever holds −1 (its clear) and (−z, z) with z ∈ [0, 1] (MAX results, never NaN, already
//    flushed where the profile flushes), and MAX of −1 with any of them is that value;
//  - front ← front so far (the pass-through): instead, the pass starts from a copy of the previous
//    front target, not a clear. Both leave max(previous front, this pass's under-blended layers)
//    in every pixel: the pixels with fragments are the same in every pass (the same draws, the
//    same opaque depth, no depth writes), and on these values (no NaN, no −0: front channels are
//    sums from +0 of non-negative terms) MAX is exact and free of order, flushing and encoding
//    being monotone;
//  - back ← 0: left out on UNORM targets only, where MAX with code 0 is the identity. Float
//    targets keep it, to be safe: were a colour channel of −0 written there, its sign would
//    depend on the order of the writes. (The test's −0 colours did not reach the back target
//    with their sign: dropping the write there too passed it, so nothing shows this case.)
struct PeelingPassWrites {
  bool passThrough = true;  // range (−1, −1) and front so far
  bool backZero = true;
};

// Which case a fragment at window depth z falls in, against its pixel's unpeeled range
// (−nearest, farthest) from the previous pass.
struct PeelCase {
  bool inside, isNearest, isFarthest;
  PeelCase(float z, const glm::vec4& range) {
    const float nearest = -range.x, farthest = range.y;
    inside = z > nearest && z < farthest;
    isNearest = z == nearest, isFarthest = z == farthest && !isNearest;
  }
};
// The nearest fragment (colour c) under the front layer so far.
glm::vec4 underFront(const glm::vec4& frontSoFar, const glm::vec4& c) {
  const float multiplier = 1.0f - frontSoFar.a;
  return {glm::vec3(frontSoFar) + glm::vec3(c) * c.a * multiplier, 1.0f - multiplier * (1.0f - c.a)};
}

// A peeling pass's shader for one fragment at window depth z with colour c: the pixel's unpeeled
// range and front layer so far from the previous pass. Targets: 0 the next range, 1 the front
// layer (this fragment under it when it is the nearest), 2 this fragment when it is the farthest.
void peel(float z, const glm::vec4& c, const glm::vec4& range, const glm::vec4& frontSoFar, PeelingPassWrites writes,
          FragmentBatchOutput& out, int i) {
  // Without branches: which case a fragment falls in follows its layers, which no predictor does.
  const PeelCase k(z, range);
  const glm::vec4 under = underFront(frontSoFar, c);
  out.writeIf(i, 0, k.inside ? glm::vec4(-z, z, 0.0f, 0.0f) : glm::vec4(-1.0f), k.inside || writes.passThrough);
  out.writeIf(i, 1, k.isNearest ? under : frontSoFar, k.isNearest || writes.passThrough);
  out.writeIf(i, 2, k.isFarthest ? c : glm::vec4(0.0f), k.isFarthest || writes.backZero);
}

// peel() over a batch where only the changing writes are kept (outputs=changing). Each
// fragment's case follows from its range alone; the front layer is fetched, and `under` formed,
// only for the nearest fragments, the only ones that write it: in a later pass nearly every
// fragment lies outside its pixel's range and writes nothing (on dense, fetching and forming them
// for every fragment was a third of a peeling pass). The same writes as peel() with
// writes.passThrough false, value for value.
void peelChanging(const FragmentBatch& in, const glm::vec4* colors, const glm::vec4* ranges, const Image& frontPrev,
                  bool backZero, FragmentBatchOutput& out) {
  for (int i = 0; i < in.count; ++i) {
    const float z = in.depth[i];
    const PeelCase k(z, ranges[i]);
    out.writeIf(i, 0, glm::vec4(-z, z, 0.0f, 0.0f), k.inside);
    if (k.isNearest) [[unlikely]] out.write(i, 1, underFront(frontPrev.fetch(in.x[i], in.y), colors[i]));
    if (k.isFarthest) [[unlikely]] out.write(i, 2, colors[i]);
    else if (backZero) out.write(i, 2, glm::vec4(0.0f));
  }
}

class Dualpeel final : public OpaqueFirstMethod {
 public:
  explicit Dualpeel(const MethodOptions& o)
      : passes_(o.integer("passes")),
        depth_{declared.color("depth_a", "rg32f", "(−nearest, farthest) unpeeled depth, ping"),
               declared.color("depth_b", "rg32f", "(−nearest, farthest) unpeeled depth, pong")},
        front_{declared.color("front_a", o.format("color"), "front layers so far, under-blended (premultiplied, alpha = coverage), ping"),
               declared.color("front_b", o.format("color"), "front layers so far, pong")},
        back_(declared.color("back", o.format("color"), "this pass's back layer (c, α)")),
        allOutputs_(o.is("outputs", "all")) {}
  const MethodInfo& info() const override { return dualpeelInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& result) override {
    const Profile& profile = context.profile;
    Image* depth[2] = {&t[depth_[0]], &t[depth_[1]]};
    Image* front[2] = {&t[front_[0]], &t[front_[1]]};
    Image& back = t[back_];
    PipelineState maxState = transparentState(profile, maxBlend());
    maxState.blend[2] = maxBlend();

    depth[0]->clear(glm::vec4(-1.0f), profile);
    front[0]->clear(glm::vec4(0.0f), profile);
    Framebuffer init;
    init.color[0] = depth[0];
    init.depth = &t.depth();
    run.transparentPositionPass("init", init, maxState, [](const FragmentBatch& in, FragmentBatchOutput& out) {
      for (int i = 0; i < in.count; ++i) out.write(i, 0, glm::vec4(-in.depth[i], in.depth[i], 0.0f, 0.0f));
    });

    Framebuffer onBackground = t.present(false);
    PipelineState over;
    over.profile = profile;
    over.blend[0] = over.blend[1] = overBlend();
    PeelingPassWrites writes;
    writes.passThrough = allOutputs_;
    writes.backZero = allOutputs_ || !back.format().isUnorm();
    int pass = 0, current = 0;
    bool exhausted = false;
    while (pass < passes_) {
      ++pass;
      const Image& depthPrev = *depth[current];
      const Image& frontPrev = *front[current];
      Image& depthNext = *depth[1 - current];
      Image& frontNext = *front[1 - current];
      depthNext.clear(glm::vec4(-1.0f), profile);
      if (writes.passThrough) frontNext.clear(glm::vec4(0.0f), profile);
      else frontNext.copyTexels(frontPrev);
      back.clear(glm::vec4(0.0f), profile);
      Framebuffer fb;
      fb.color[0] = &depthNext;
      fb.color[1] = &frontNext;
      fb.color[2] = &back;
      fb.depth = &t.depth();
      // A batch at a time: the previous range and front layer fetched a row at a time.
      run.transparentBatchPass("peel " + std::to_string(pass), fb, maxState,
                               [&](const FragmentBatch& in, const glm::vec4* colors, FragmentBatchOutput& out) {
                                 glm::vec4 ranges[kShaderBatch], fronts[kShaderBatch];
                                 fetchTexels(depthPrev, in, ranges);
                                 if (!writes.passThrough) return peelChanging(in, colors, ranges, frontPrev, writes.backZero, out);
                                 fetchTexels(frontPrev, in, fronts);
                                 for (int i = 0; i < in.count; ++i) peel(in.depth[i], colors[i], ranges[i], fronts[i], writes, out, i);
                               });
      // The back layer OVER the background; the draw count is the sample's occlusion query.
      run.fullscreenPass("blend back " + std::to_string(pass), onBackground, over,
                         [&](const FragmentInput& in, FragmentOutput& o) {
                           const glm::vec4 b = back.fetch(in.x, in.y);
                           if (b.a == 0.0f) return o.discard();
                           o.write(0, b);
                           o.write(1, b);
                         });
      current = 1 - current;
      if (result.passes.back().stats.fragmentsWritten == 0) {
        exhausted = true;
        break;
      }
    }
    // C = front.rgb + C_background·(1 − front.a).
    PipelineState merge;
    merge.profile = profile;
    merge.blend[0] = merge.blend[1] = detail::states::kFrontOntoBackground;
    const Image& frontFinal = *front[current];
    run.fullscreenPass("merge front", onBackground, merge, [&](const FragmentInput& in, FragmentOutput& o) {
      const glm::vec4 f = frontFinal.fetch(in.x, in.y);
      o.write(0, f);
      o.write(1, f);
    });
    // The occlusion query also ends the loop when every back layer of a pass has α = 0 (fully
    // transparent texels), with layers still inside some pixels' ranges: the last pass's range
    // target says whether any fragment was left (a range other than the cleared (−1, −1)).
    bool layersLeft = false;
    const Image& rangeLeft = *depth[current];
    for (int y = 0; y < rangeLeft.height() && !layersLeft; ++y)
      for (int x = 0; x < rangeLeft.width() && !layersLeft; ++x) layersLeft = rangeLeft.fetch(x, y).y >= 0.0f;
    result.stats.peelingPasses = pass;
    result.stats.allLayersPeeled = exhausted && !layersLeft;
    if (!exhausted) result.stats.layersLeftBecause = "raise passes";
    else if (layersLeft)
      result.stats.layersLeftBecause =
          "a pass peeled only fully transparent back layers, which the occlusion query counts as nothing";
  }

 private:
  int passes_;
  ColorHandle depth_[2], front_[2], back_;  // ping and pong
  bool allOutputs_;
};

}  // namespace

const MethodInfo& dualpeelInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "dualpeel",
      "dual depth peeling (Bavoil–Myers 2008): nearest and farthest layer per pass, MAX blending",
      {{"passes", "64", "peeling passes at most (⌈layers/2⌉ + 1 are needed)", {}, OptionNumber::integer(1, 1024)},
       {"color", "rgba8", "format of the front and back colour targets (as peel's layers)", {"rgba8", "rgba16f", "rgba32f"}},
       {"outputs", "changing",
        "changing: a peeling pass writes only what can change a target (the previous front copied, not passed through); "
        "all: every output of the sample's shader. The same bits",
        {"changing", "all"}}}};
    i.studyVariants = {{{"color", "rgba32f"}}, {{"passes", "4"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> dualpeelFactory(const MethodOptions& o) {
  return std::make_unique<Dualpeel>(o);
}

}  // namespace oitref::methods
