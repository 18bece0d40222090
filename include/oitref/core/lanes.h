// One spelling for a scalar and for GCC/Clang vector lanes, so that a conversion rule is written
// once and runs on one fragment (the per-fragment path, the oracle) or on four at a time (the
// span kernels) with the same IEEE operations in every lane.
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

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

// The lanes of V loaded one element at a time, put together in registers. For memory written one
// element at a time just before: a vector load that spans several narrower stores still in
// flight cannot take their data (no store forwarding) and waits until they retire, which costs
// more than the loads. The empty asm keeps the compiler from merging the loads into a vector load.
template <typename V, typename T>
inline V loadEachLane(const T* p) {
  auto lane = [p](size_t i) {
    T x;
    std::memcpy(&x, p + i, sizeof x);  // (not p[i]: GCC then warns of lanes past a count it cannot bound)
#if defined(__x86_64__)
    asm("" : "+x"(x));
#endif
    return x;
  };
  return [&]<size_t... L>(std::index_sequence<L...>) { return V{lane(L)...}; }(std::make_index_sequence<sizeof(V) / sizeof(T)>());
}

}  // namespace oitref::lanes
