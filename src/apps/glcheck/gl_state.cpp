#include "glcheck/gl_state.h"

#include "glcheck/gl_format.h"

namespace oitref::glcheck {
namespace {

GLenum glCompareFunc(CompareFunc f) {
  constexpr GLenum table[] = {GL_NEVER, GL_LESS, GL_EQUAL, GL_LEQUAL, GL_GREATER, GL_NOTEQUAL, GL_GEQUAL, GL_ALWAYS};
  return table[size_t(f)];
}

}  // namespace

void applyBlendState(const GlFunctions& gl, unsigned i, const BlendState& b) {
  if (b.enabled) gl.Enablei(GL_BLEND, i);
  else gl.Disablei(GL_BLEND, i);
  gl.BlendEquationSeparatei(i, glBlendEquation(b.equationRgb), glBlendEquation(b.equationAlpha));
  gl.BlendFuncSeparatei(i, glBlendFactor(b.srcRgb), glBlendFactor(b.dstRgb), glBlendFactor(b.srcAlpha),
                        glBlendFactor(b.dstAlpha));
  gl.ColorMaski(i, b.writeMask & 1u, (b.writeMask >> 1) & 1u, (b.writeMask >> 2) & 1u, (b.writeMask >> 3) & 1u);
}

void applyPipelineState(const GlFunctions& gl, const PipelineState& s, int colourCount) {
  if (s.depth.testEnabled) gl.Enable(GL_DEPTH_TEST);
  else gl.Disable(GL_DEPTH_TEST);
  gl.DepthFunc(glCompareFunc(s.depth.func));
  gl.DepthMask(s.depth.writeMask ? GL_TRUE : GL_FALSE);
  if (s.depth.clamp) gl.Enable(GL_DEPTH_CLAMP);
  else gl.Disable(GL_DEPTH_CLAMP);
  if (s.raster.cull == CullMode::None) {
    gl.Disable(GL_CULL_FACE);
  } else {
    gl.Enable(GL_CULL_FACE);
    gl.CullFace(s.raster.cull == CullMode::Front ? GL_FRONT : GL_BACK);
  }
  gl.FrontFace(s.raster.frontFace == FrontFace::CounterClockwise ? GL_CCW : GL_CW);
  for (int i = 0; i < colourCount; ++i) applyBlendState(gl, unsigned(i), s.blend[size_t(i)]);
  gl.BlendColor(s.blendConstant.r, s.blendConstant.g, s.blendConstant.b, s.blendConstant.a);
}

}  // namespace oitref::glcheck
