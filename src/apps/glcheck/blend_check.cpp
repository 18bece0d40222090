#include "glcheck/blend_check.h"

#include <cstring>
#include <stdexcept>

#include "glcheck/gl_format.h"
#include "gpucapture/blend_capture.h"

namespace oitref::glcheck {

std::vector<tools::RecordedTexels> runBlendCases(const GlContext& context, const std::vector<tools::BlendCase>& cases) {
  std::vector<GlBlendCase> gl;
  gl.reserve(cases.size());
  for (const tools::BlendCase& c : cases) {
    const auto f = glFormatOf(c.format);
    if (!f) throw std::invalid_argument("format " + c.format.name() + " has no OpenGL equivalent");
    GlBlendCase g{};
    g.format = GlTargetFormat{f->internalFormat, f->readFormat, f->readType, c.format.bytesPerTexel()};
    g.equationRgb = glBlendEquation(c.state.equationRgb);
    g.equationAlpha = glBlendEquation(c.state.equationAlpha);
    g.srcRgb = glBlendFactor(c.state.srcRgb);
    g.dstRgb = glBlendFactor(c.state.dstRgb);
    g.srcAlpha = glBlendFactor(c.state.srcAlpha);
    g.dstAlpha = glBlendFactor(c.state.dstAlpha);
    std::memcpy(g.constant.data(), &c.constant[0], 16);
    std::memcpy(g.destination.data(), &c.destination[0], 16);
    std::memcpy(g.source.data(), &c.source[0], 16);
    gl.push_back(g);
  }
  const std::vector<GlTexels> texels = captureBlendCases(context.gl(), gl);
  std::vector<tools::RecordedTexels> out(texels.size());
  for (size_t i = 0; i < texels.size(); ++i) out[i] = {texels[i].destination, texels[i].result};
  return out;
}

}  // namespace oitref::glcheck
