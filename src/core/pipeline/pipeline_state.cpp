#include "oitref/core/pipeline_state.h"

#include <sstream>

namespace oitref {

const char* toString(CullMode m) {
  switch (m) {
    case CullMode::None: return "none";
    case CullMode::Front: return "front";
    case CullMode::Back: return "back";
  }
  return "?";
}

const char* toString(FillConvention f) { return f == FillConvention::TopLeft ? "top_left" : "bottom_left"; }

std::string PipelineState::describe() const {
  std::ostringstream s;
  s << "raster: subpixel_bits=" << raster.subpixelBits << " cull=" << toString(raster.cull)
    << " front_face=" << (raster.frontFace == FrontFace::CounterClockwise ? "ccw" : "cw")
    << " fill=" << toString(raster.fill) << "\n";
  s << "depth: test=" << (depth.testEnabled ? "on" : "off") << " func=" << toString(depth.func)
    << " write=" << (depth.writeMask ? "on" : "off") << " clamp=" << (depth.clamp ? "on" : "off") << "\n";
  for (int i = 0; i < kMaxColorTargets; ++i)
    if (!(blend[size_t(i)] == BlendState{})) s << "blend[" << i << "]: " << blend[size_t(i)].describe() << "\n";
  s << "blend_constant: " << blendConstant.r << "," << blendConstant.g << "," << blendConstant.b << ","
    << blendConstant.a << "\n";
  s << "viewport: " << viewport.x << "," << viewport.y << "," << viewport.width << "," << viewport.height
    << (viewport.width == 0 ? " (whole framebuffer)" : "") << "\n";
  s << "profile: " << profile.describe() << "\n";
  return s.str();
}

}  // namespace oitref
