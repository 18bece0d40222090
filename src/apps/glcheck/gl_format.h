// How each oitref colour format is named in OpenGL: the sized internal format of the texture and
// the (format, type) pair that reads a texel back in its own bits (GL 4.6 §8.4.4 tables 8.2,
// 8.5, 8.8; §18.2.4 ReadPixels), so the bytes GL returns are laid out exactly as oitref stores
// the texel (see oitref/core/format.h).
#pragma once

#include <optional>

#include "glcheck/gl_functions.h"
#include "oitref/core/blend_state.h"
#include "oitref/core/format.h"

namespace oitref::glcheck {

struct GlFormat {
  GLenum internalFormat, readFormat, readType;
};

// nullopt for formats GL does not have (user minifloats).
std::optional<GlFormat> glFormatOf(const Format& format);

GLenum glBlendEquation(BlendEquation e);
GLenum glBlendFactor(BlendFactor f);

}  // namespace oitref::glcheck
