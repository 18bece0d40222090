// x^n for integer n ≥ 0 by binary exponentiation in fp32: a fixed sequence of multiplications,
// so the bits do not depend on a C library's pow (GPUs evaluate pow as exp2(n·log2 x), which
// is neither).
#pragma once

namespace oitref::methods {

inline float powInt(float x, unsigned n) {
  float result = 1.0f;
  while (n) {
    if (n & 1u) result *= x;
    x *= x;
    n >>= 1;
  }
  return result;
}

}  // namespace oitref::methods
