// Inline fp16 conversion for the hot paths (blending, clears). Same bits as oitref/fp16.h.
#pragma once

#include <cstdint>

#include "oitref/minifloat.h"
#if defined(OITREF_HAVE_F16C)
#include <immintrin.h>
#endif

namespace oitref::detail {

inline uint16_t encodeHalfInline(float value, Rounding rounding) {
#if defined(OITREF_HAVE_F16C)
  if (rounding == Rounding::TowardZero) return _cvtss_sh(value, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
  return _cvtss_sh(value, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
#else
  return static_cast<uint16_t>(encodeMinifloat(value, kHalfSpec, rounding));
#endif
}

inline float decodeHalfInline(uint16_t bits) {
#if defined(OITREF_HAVE_F16C)
  return _cvtsh_ss(bits);
#else
  return decodeMinifloat(bits, kHalfSpec);
#endif
}

}  // namespace oitref::detail
