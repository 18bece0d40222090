// Arithmetic shared by the moment reconstruction (moment_math.cpp) and the root finders
// (polynomial_roots.cpp): complex numbers written out, and one spelling of a rule's operations
// for one value and for vector lanes.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "oitref/core/lanes.h"

namespace oitref::methods {

// Complex arithmetic written out, so each operation rounds as written: in fp32 as the shader's
// vec2 code does (Cf), and in double for the root finder, where the library's division and abs
// (__divdc3, hypot) also dominated the time (Cd).
template <typename T>
struct Cx {
  T x{}, y{};
};
template <typename T> Cx<T> operator+(Cx<T> a, Cx<T> b) { return {a.x + b.x, a.y + b.y}; }
template <typename T> Cx<T> operator-(Cx<T> a, Cx<T> b) { return {a.x - b.x, a.y - b.y}; }
template <typename T> Cx<T> operator*(Cx<T> a, Cx<T> b) { return {a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x}; }
template <typename T> Cx<T> operator*(Cx<T> a, T s) { return {a.x * s, a.y * s}; }
template <typename T> Cx<T> conj(Cx<T> a) { return {a.x, -a.y}; }
template <typename T> T norm(Cx<T> a) { return a.x * a.x + a.y * a.y; }
template <typename T> Cx<T> divide(Cx<T> a, Cx<T> b) {  // a·conj(b) / |b|²
  const Cx<T> n = a * conj(b);
  const T d = norm(b);
  return {n.x / d, n.y / d};
}
using Cf = Cx<float>;
using Cd = Cx<double>;

// Lanes: one value (float or double, with bool comparisons) or a vector of them (v8f for the
// four-moment closed form, lanes::d4 for the root finder, −1/0 integer lanes), so that a rule is
// written once and a batch's lanes run the scalar operations side by side.
typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));
using d4Mask = decltype(lanes::d4{} < lanes::d4{});
template <typename F>
using MaskOf = std::conditional_t<std::is_arithmetic_v<F>, bool, std::conditional_t<std::is_same_v<F, v8f>, v8i, d4Mask>>;
template <typename F>
inline F splatF(float v) {
  return v - F{};  // v − (+0) keeps −0 (lanes::splat)
}
inline float selectF(bool m, float a, float b) { return m ? a : b; }
inline double selectF(bool m, double a, double b) { return m ? a : b; }
inline v8f selectF(v8i m, v8f a, v8f b) { return m ? a : b; }
inline lanes::d4 selectF(d4Mask m, lanes::d4 a, lanes::d4 b) { return m ? a : b; }
inline bool anyLane(bool m) { return m; }
inline bool anyLane(d4Mask m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }
inline bool anyLane(v8i m) {
#if defined(__AVX__)
  return _mm256_movemask_ps((__m256)m) != 0;
#else
  return (m[0] | m[1] | m[2] | m[3] | m[4] | m[5] | m[6] | m[7]) != 0;
#endif
}
// out[l] = (m[l] != 0) for the eight lanes, stored at once: the lanes' sign bits (movemask) and
// a table of their bytes. Left to a loop, GCC extracted and stored the lanes one at a time, a
// sixth of the four-moment bound's time.
inline void storeLaneFlags(v8i m, bool* out) {
#if defined(__AVX__)
  static constexpr auto kBytes = [] {
    struct Table {
      uint64_t of[256] = {};
    } t;
    for (unsigned bits = 0; bits < 256; ++bits)
      for (int l = 0; l < 8; ++l) t.of[bits] |= uint64_t(bits >> l & 1) << (8 * l);
    return t;
  }();
  const uint64_t bytes = kBytes.of[unsigned(_mm256_movemask_ps((__m256)m))];
  static_assert(sizeof(bool) == 1);
  std::memcpy(out, &bytes, sizeof bytes);
#else
  for (int l = 0; l < 8; ++l) out[l] = m[l] != 0;
#endif
}
// IEEE square root, per lane.
inline float sqrtF(float x) { return std::sqrt(x); }
inline double sqrtF(double x) { return std::sqrt(x); }
inline v8f sqrtF(v8f x) {
#if defined(__AVX__)
  return (v8f)_mm256_sqrt_ps((__m256)x);  // per lane, without std::sqrt's errno branch per lane
#else
  v8f r;
  for (int i = 0; i < 8; ++i) r[i] = std::sqrt(x[i]);
  return r;
#endif
}
inline lanes::d4 sqrtF(lanes::d4 x) {
#if defined(__AVX__)
  return (lanes::d4)_mm256_sqrt_pd((__m256d)x);
#else
  for (int i = 0; i < 4; ++i) x[i] = std::sqrt(x[i]);
  return x;
#endif
}
// isfinite, with floating-point operations only: x − x is 0 for finite x and NaN for ±inf, NaN.
template <typename F>
inline MaskOf<F> finiteF(F x) {
  return (x - x) == splatF<F>(0.0f);
}

}  // namespace oitref::methods
