// Blend state of one colour attachment, as plain data with GL's initial values
// (GL 4.6 §17.3.6: blending disabled, FUNC_ADD, ONE, ZERO, all channels written).
#pragma once

#include <cstdint>
#include <string>

namespace oitref {

enum class BlendEquation : uint8_t { Add, Subtract, ReverseSubtract, Min, Max };

enum class BlendFactor : uint8_t {
  Zero, One,
  SrcColor, OneMinusSrcColor, DstColor, OneMinusDstColor,
  SrcAlpha, OneMinusSrcAlpha, DstAlpha, OneMinusDstAlpha,
  ConstantColor, OneMinusConstantColor, ConstantAlpha, OneMinusConstantAlpha,
  SrcAlphaSaturate,
};

struct BlendState {
  bool enabled = false;
  BlendEquation equationRgb = BlendEquation::Add;
  BlendEquation equationAlpha = BlendEquation::Add;
  BlendFactor srcRgb = BlendFactor::One;
  BlendFactor dstRgb = BlendFactor::Zero;
  BlendFactor srcAlpha = BlendFactor::One;
  BlendFactor dstAlpha = BlendFactor::Zero;
  uint8_t writeMask = 0xf;  // bit c set: channel c (r, g, b, a) is written

  constexpr bool operator==(const BlendState&) const = default;
  std::string describe() const;  // "add,add src_alpha,one_minus_src_alpha,one,one mask=rgba"

  // Common configurations.
  static constexpr BlendState disabled() { return {}; }
  static constexpr BlendState separate(BlendEquation eqRgb, BlendEquation eqAlpha, BlendFactor sRgb, BlendFactor dRgb,
                             BlendFactor sA, BlendFactor dA) {
    return BlendState{true, eqRgb, eqAlpha, sRgb, dRgb, sA, dA, 0xf};
  }
  static constexpr BlendState same(BlendEquation eq, BlendFactor src, BlendFactor dst) {
    return separate(eq, eq, src, dst, src, dst);
  }
};

const char* toString(BlendEquation e);
const char* toString(BlendFactor f);
// Names as the CLI and CSV take them: "add", "reverse_subtract", "one_minus_src_alpha", ...
// Throw std::invalid_argument listing the valid names.
BlendEquation parseBlendEquation(const std::string& name);
BlendFactor parseBlendFactor(const std::string& name);
// An enabled state from the CLI's two texts: `equation` "EQ" or "EQ_RGB,EQ_ALPHA", `func` "SRC,DST"
// or "SRC_RGB,DST_RGB,SRC_ALPHA,DST_ALPHA". Throws std::invalid_argument naming the text as
// `equationName` or `funcName` (e.g. "--equation") when it has the wrong number of names.
BlendState parseBlendState(const std::string& equation, const std::string& func,
                           const std::string& equationName = "equation", const std::string& funcName = "func");

}  // namespace oitref
