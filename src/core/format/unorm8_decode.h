// k/255 correctly rounded, for every 8-bit code k: decodeUnorm(k, 8) (oitref/core/unorm.h) as a table,
// for the per-texel paths (texel fetches, the blend kernels' destination reads).
#pragma once

#include <array>
#include <cstdint>

#include "oitref/core/unorm.h"

namespace oitref::detail {

inline const std::array<float, 256> kUnorm8Decode = [] {
  std::array<float, 256> t{};
  for (uint32_t k = 0; k < 256; ++k) t[k] = decodeUnorm(k, 8);
  return t;
}();
// The same for llvmpipe's texel fetches (decodeUnorm8Llvmpipe): Image::decodeFetchesAs.
inline const std::array<float, 256> kUnorm8DecodeLlvmpipe = [] {
  std::array<float, 256> t{};
  for (uint32_t k = 0; k < 256; ++k) t[k] = decodeUnorm8Llvmpipe(k);
  return t;
}();

}  // namespace oitref::detail
