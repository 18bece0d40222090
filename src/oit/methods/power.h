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

// powInt(x, N) with N known at compile time: the same multiplications in the same order,
// unrolled, so that a loop over fragments that calls it has no inner loop and runs in vector lanes.
template <unsigned N>
inline float powInt(float x, float result = 1.0f) {
  if constexpr (N == 0) return result;
  else return powInt<(N >> 1)>(x * x, (N & 1u) ? result * x : result);
}

}  // namespace oitref::methods
