#include "glcheck/gl_format.h"

namespace oitref::glcheck {

std::optional<GlFormat> glFormatOf(const Format& f) {
  switch (f.id) {
    case FormatId::R8: return GlFormat{GL_R8, GL_RED, GL_UNSIGNED_BYTE};
    case FormatId::RG8: return GlFormat{GL_RG8, GL_RG, GL_UNSIGNED_BYTE};
    case FormatId::RGBA8: return GlFormat{GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
    case FormatId::R16: return GlFormat{GL_R16, GL_RED, GL_UNSIGNED_SHORT};
    case FormatId::RG16: return GlFormat{GL_RG16, GL_RG, GL_UNSIGNED_SHORT};
    case FormatId::RGBA16: return GlFormat{GL_RGBA16, GL_RGBA, GL_UNSIGNED_SHORT};
    case FormatId::RGB10A2: return GlFormat{GL_RGB10_A2, GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV};
    case FormatId::R16F: return GlFormat{GL_R16F, GL_RED, GL_HALF_FLOAT};
    case FormatId::RG16F: return GlFormat{GL_RG16F, GL_RG, GL_HALF_FLOAT};
    case FormatId::RGBA16F: return GlFormat{GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT};
    case FormatId::R32F: return GlFormat{GL_R32F, GL_RED, GL_FLOAT};
    case FormatId::RG32F: return GlFormat{GL_RG32F, GL_RG, GL_FLOAT};
    case FormatId::RGBA32F: return GlFormat{GL_RGBA32F, GL_RGBA, GL_FLOAT};
    case FormatId::R11G11B10F: return GlFormat{GL_R11F_G11F_B10F, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV};
    case FormatId::Minifloat: return std::nullopt;
  }
  return std::nullopt;
}

GLenum glBlendEquation(BlendEquation e) {
  switch (e) {
    case BlendEquation::Add: return GL_FUNC_ADD;
    case BlendEquation::Subtract: return GL_FUNC_SUBTRACT;
    case BlendEquation::ReverseSubtract: return GL_FUNC_REVERSE_SUBTRACT;
    case BlendEquation::Min: return GL_MIN;
    case BlendEquation::Max: return GL_MAX;
  }
  return GL_FUNC_ADD;
}

GLenum glBlendFactor(BlendFactor f) {
  constexpr GLenum table[] = {GL_ZERO,           GL_ONE,
                              GL_SRC_COLOR,      GL_ONE_MINUS_SRC_COLOR,
                              GL_DST_COLOR,      GL_ONE_MINUS_DST_COLOR,
                              GL_SRC_ALPHA,      GL_ONE_MINUS_SRC_ALPHA,
                              GL_DST_ALPHA,      GL_ONE_MINUS_DST_ALPHA,
                              GL_CONSTANT_COLOR, GL_ONE_MINUS_CONSTANT_COLOR,
                              GL_CONSTANT_ALPHA, GL_ONE_MINUS_CONSTANT_ALPHA,
                              GL_SRC_ALPHA_SATURATE};
  return table[size_t(f)];
}

}  // namespace oitref::glcheck
