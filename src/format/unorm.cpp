#include "oitref/unorm.h"

#include <cmath>

namespace oitref {

uint32_t encodeUnorm(float value, int bits, UnormRounding rounding) {
  const uint32_t maxCode = (uint32_t(1) << bits) - 1;
  const float v = clampUnit(value);
  if (rounding == UnormRounding::Fp32Product) {
    const float product = v * float(maxCode);  // rounded to fp32 first
    return uint32_t(std::nearbyint(product));  // default FP environment: ties to even
  }
  // f has 24 significant bits, 2^b−1 at most b: the double product is exact for b ≤ 29.
  const double product = double(v) * double(maxCode);
  return uint32_t(std::nearbyint(product));
}

float decodeUnorm(uint32_t code, int bits) {
  const uint32_t maxCode = (uint32_t(1) << bits) - 1;
  return float(code) / float(maxCode);  // one correctly rounded division
}

}  // namespace oitref
