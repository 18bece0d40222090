// One spelling for a scalar and for GCC/Clang vector lanes, so that a conversion rule is written
// once and runs on one fragment (the per-fragment path, the oracle) or on four at a time (the
// span kernels) with the same IEEE operations in every lane.
#pragma once

#include <cstdint>
#include <type_traits>

namespace oitref::lanes {

typedef double d4 __attribute__((vector_size(32)));
typedef float f4 __attribute__((vector_size(16)));
typedef int32_t i4 __attribute__((vector_size(16)));
typedef uint32_t u4 __attribute__((vector_size(16)));

template <typename T>
constexpr bool isVector = !std::is_arithmetic_v<T>;

// The lane types that go with a double type: fp32, int32 and uint32, scalar or four lanes.
template <typename D>
struct With {
  using Float = float;
  using Int = int32_t;
  using Uint = uint32_t;
};
template <>
struct With<d4> {
  using Float = f4;
  using Int = i4;
  using Uint = u4;
};

// C's conversion lane by lane (floating → integer truncates toward zero). A comparison's result
// (bool, or −1/0 lanes) becomes 1/0 or −1/0: use its lowest bit.
template <typename To, typename From>
inline To convert(From v) {
  if constexpr (isVector<From>) return __builtin_convertvector(v, To);
  else return To(v);
}

// The constant v in every lane. As v − 0, not 0 + v: a sum of zeros is +0 where v is −0, and
// lanes must hold what the scalar holds (x − (+0) = x for every x, −0 included).
template <typename T>
inline T splat(double v) {
  if constexpr (isVector<T>) return v - T{};
  else return T(v);
}

// Logical and / or of comparisons' results: && and || on bools, & and | on −1/0 lanes.
template <typename M>
inline M both(M a, M b) {
  if constexpr (isVector<M>) return a & b;
  else return a && b;
}
template <typename M>
inline M either(M a, M b) {
  if constexpr (isVector<M>) return a | b;
  else return a || b;
}

// Logical not of a comparison's result: !b, or ~m of −1/0 lanes.
template <typename M>
inline M negate(M m) {
  if constexpr (isVector<M>) return ~m;
  else return !m;
}

}  // namespace oitref::lanes
