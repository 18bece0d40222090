// Front-to-back depth peeling (Everitt 2001), Rožek's thesis Algorithm 1. Each pass renders the
// transparent geometry as if solid into C2/D2 (D2 starts as the opaque depth), discarding what
// is not strictly behind the previous layer D3 — so each pass keeps the nearest layer not yet
// peeled (coplanar fragments are lost, as in the original). The layer, written as (c·α, α), is
// blended under the accumulator C3:
//   RGB:   C3 = C2·α_d + C3        (src DST_ALPHA, dst ONE)
//   alpha: C3 = C3·(1 − α_s)       (src ZERO, dst ONE_MINUS_SRC_ALPHA)
// and finally C3 is blended onto the background: C1 = C3.rgb + C1·C3.a (src ONE, dst SRC_ALPHA).
// Depths are compared in the depth buffer's own representation (d24). The method runs `passes`
// iterations as a GPU loop would and reports how many actually peeled something.
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

class Peel final : public OpaqueFirstMethod {
 public:
  explicit Peel(const MethodOptions& o)
      : passes_(o.integer("passes")),
        layer_(declared.color("layer", o.format("layer"), "C2: the layer peeled this pass, (c·α, α)")),
        layerDepth_(declared.depth("layer_depth", DepthFormat::D24, "D2: depth of the layer peeled this pass")),
        peeledDepth_(declared.depth("peeled_depth", DepthFormat::D24, "D3: depth of the previous layer")),
        accum_(declared.color("accum", o.format("layer"), "C3: layers so far, front to back; alpha = transmittance")) {}
  const MethodInfo& info() const override { return peelInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& result) override {  // after steps 2–3, the opaque pass
    Image& layer = t[layer_];
    Image& accum = t[accum_];
    DepthBuffer& layerDepth = t[layerDepth_];
    DepthBuffer& peeledDepth = t[peeledDepth_];
    accum.clear({0, 0, 0, 1}, context.profile);                    // step 1
    peeledDepth.clear(0.0);
    Framebuffer layerFb;
    layerFb.color[0] = &layer;
    layerFb.depth = &layerDepth;
    PipelineState solid;
    solid.profile = context.profile;
    solid.depth = {true, CompareFunc::Less, true, false};
    Framebuffer accumFb;
    accumFb.color[0] = &accum;
    PipelineState under;
    under.profile = context.profile;
    under.blend[0] = underBlend();  // steps 8–10
    int peeledPasses = 0;
    bool exhausted = false;
    for (int pass = 0; pass < passes_; ++pass) {                    // step 4
      layerDepth = t.depth();                                       // step 5: D2 ← D1
      layerFb.clearColor[0] = glm::vec4(0.0f);                      // step 6, by the draw (tile by tile)
      const DepthFormat format = peeledDepth.format();
      // The fragment is kept where it lies strictly behind the previous layer: the shader's own
      // depth test, declared so that the pipeline can skip shading what it discards.
      // The shader reads D3 as the profile's texelFetch returns it and rounds that back to a code
      // (depthCodeAsFetched), as the GLSL version must: under llvmpipe's, a code near 1 can come
      // back one or two away from the stored one (glcheck).
      const TextureFiltering read = context.profile.texture;
      const ShaderDepthTest behindPeeled{&peeledDepth, CompareFunc::Greater, read};
      run.transparentBatchPass("peel " + std::to_string(pass + 1), layerFb, solid,  // step 7
                               [&](const FragmentBatch& in, const glm::vec4* colors, FragmentBatchOutput& out) {
                                 for (int i = 0; i < in.count; ++i) {
                                   if (!depthTestPasses(behindPeeled.func, encodeDepth(in.depth[i], format),
                                                        depthCodeAsFetched(peeledDepth.load(in.x[i], in.y), format, read),
                                                        format)) {
                                     out.discard(i);
                                     continue;
                                   }
                                   const glm::vec4& c = colors[i];
                                   out.write(i, 0, premultiplied(c));
                                 }
                               },
                               /*mayDiscard=*/true, /*pure=*/true, behindPeeled);
      const uint64_t peeled = result.passes.back().stats.fragmentsWritten;
      if (peeled == 0) exhausted = true;
      else ++peeledPasses;
      run.fullscreenProgram("under " + std::to_string(pass + 1), accumFb, under,  // step 11
                            programOfBatch([&](const FragmentBatch& in, FragmentBatchOutput& out) {
                              glm::vec4 c[kShaderBatch];
                              fetchTexels(layer, in, c);
                              for (int i = 0; i < in.count; ++i) out.write(i, 0, c[i]);
                            }));
      peeledDepth = layerDepth;                                     // step 13: D3 ← D2
    }
    // Step 15: C1 = C3.rgb + C1·C3.a.
    Framebuffer out = t.present(false);
    PipelineState merge;
    merge.profile = context.profile;
    merge.blend[0] = merge.blend[1] = premultipliedOntoBackgroundBlend();
    run.fullscreenPass("merge", out, merge, [&](const FragmentInput& in, FragmentOutput& o) {
      const glm::vec4 c = accum.fetch(in.x, in.y);
      o.write(0, c);
      o.write(1, c);
    });
    result.stats.peelingPasses = passes_;  // the thesis draws them all (step 4)
    result.stats.layersPeeled = peeledPasses;
    result.stats.allLayersPeeled = exhausted;
    if (!exhausted) result.stats.layersLeftBecause = "raise passes";
  }

 private:
  int passes_;
  ColorHandle layer_;
  DepthHandle layerDepth_, peeledDepth_;
  ColorHandle accum_;
};

}  // namespace

const MethodInfo& peelInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{"peel",
                 "front-to-back depth peeling (Everitt; thesis Algorithm 1)",
                 {{"passes", "32", "peeling iterations (the thesis: 32)", {}, OptionNumber::integer(1, 1024)},
                  {"layer", "rgba8", "format of the peeled layer and the accumulator (thesis: RGBA8)",
                   {"rgba8", "rgba16f", "rgba32f"}}},
                 {{"thesis", "Algorithm 1 (the default): 32 iterations, RGBA8 C2 and C3", {{"passes", "32"}, {"layer", "rgba8"}}}}};
    i.studyVariants = {{{"passes", "1"}}, {{"passes", "2"}}, {{"passes", "4"}}, {{"passes", "8"}}, {{"passes", "16"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> peelFactory(const MethodOptions& o) {
  return std::make_unique<Peel>(o);
}

}  // namespace oitref::methods
