// The state of one draw, as plain, comparable, printable data. Defaults are GL's initial state
// except where noted. Workers receive it by value; there is no global state.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <glm/vec4.hpp>

#include "oitref/core/blend_state.h"
#include "oitref/core/depth.h"
#include "oitref/core/profile.h"

namespace oitref {

inline constexpr int kMaxColorTargets = 8;

enum class CullMode : uint8_t { None, Front, Back };  // default None: transparent geometry shows both faces
enum class FrontFace : uint8_t { CounterClockwise, Clockwise };  // glFrontFace(GL_CCW)

// Which pixel-centre samples on an edge belong to the triangle (GL 4.6 §14.6.1 only asks that
// exactly one of two triangles sharing an edge covers them). "Top" means larger window y, i.e.
// towards the top row of the written image.
//  TopLeft:    samples on a top edge (horizontal, interior below) or a left edge are inside.
//  BottomLeft: samples on a bottom edge (horizontal, interior above) or a left edge are inside.
enum class FillConvention : uint8_t { TopLeft, BottomLeft };

struct RasterState {
  int subpixelBits = 8;  // window coordinates snap to 1/2^bits pixel; 1..8 supported
  CullMode cull = CullMode::None;
  FrontFace frontFace = FrontFace::CounterClockwise;
  FillConvention fill = FillConvention::TopLeft;
  bool operator==(const RasterState&) const = default;
};

// glViewport; width = height = 0 means the whole framebuffer. Depth range is fixed at [0,1].
struct Viewport {
  int x = 0, y = 0, width = 0, height = 0;
  bool operator==(const Viewport&) const = default;
};

struct PipelineState {
  RasterState raster;
  DepthState depth;
  std::array<BlendState, kMaxColorTargets> blend{};  // per colour attachment (glBlendFunci, glColorMaski)
  glm::vec4 blendConstant{0.0f};                      // glBlendColor
  Viewport viewport;
  Profile profile;

  bool operator==(const PipelineState&) const = default;
  std::string describe() const;  // every field, one per line
};

const char* toString(CullMode m);
const char* toString(FillConvention f);

}  // namespace oitref
