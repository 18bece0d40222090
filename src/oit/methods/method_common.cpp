#include "methods/method_common.h"

namespace oitref::methods {

Framebuffer weightedAccumulationTargets(FrameTargets& targets, Image& accum, Image& reveal) {
  Framebuffer fb;
  fb.color[0] = &accum;
  fb.color[1] = &reveal;
  fb.depth = &targets.depth();
  fb.clearColor[0] = glm::vec4(0.0f);  // the pass clears them first (tile by tile: Framebuffer::clearColor)
  fb.clearColor[1] = glm::vec4(1.0f);
  return fb;
}

PipelineState weightedAccumulationState(const Profile& profile) {
  PipelineState st = transparentState(profile, additiveBlend());
  st.blend[1] = revealageBlend();
  return st;
}

void compositeWeighted(PassRunner& run, FrameTargets& targets, const Image& accum, const Image& reveal,
                       ResolveClamp clamp) {
  run.blendOverBackgroundBatch(targets, [&](const FragmentBatch& in, glm::vec4* s) {
    glm::vec4 accumScratch[kShaderBatch];
    float revealScratch[kShaderBatch];
    weightedResolveRow(texelsOf(accum, in, accumScratch), redTexelsOf(reveal, in, revealScratch), in.count, s, clamp);
  });
}

}  // namespace oitref::methods
