// oitref's draw state (oitref/core/pipeline_state.h) set on a GL context, so a GL pass runs with the
// very state object the emulated pass uses.
#pragma once

#include "glcheck/gl_functions.h"
#include "oitref/core/pipeline_state.h"

namespace oitref::glcheck {

// glEnablei/glDisablei(GL_BLEND, i), glBlendEquationSeparatei, glBlendFuncSeparatei, glColorMaski.
void applyBlendState(const GlFunctions& gl, unsigned drawBuffer, const BlendState& blend);
// Depth test, function and write mask; blending of draw buffers 0..colourCount−1; the blend
// constant. Viewport, culling (none) and the raster rules are GL's defaults, as oitref's.
void applyPipelineState(const GlFunctions& gl, const PipelineState& state, int colourCount);

}  // namespace oitref::glcheck
