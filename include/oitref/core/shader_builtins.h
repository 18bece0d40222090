// GLSL builtins whose precision the GLSL specification leaves open (§4.1.9 of GLSL 4.60 gives
// exp2 and log2 only "3 + 2·|x| ULP"), as a profile's driver computes them, for the C++ shaders
// that mirror the methods' GLSL (the profile's `math`).
//
// llvmpipe (Mesa 22.3.6): GLSL's log(x) and exp(x) reach LLVM as log2(x)·(1/log2 e) and
// exp2(x·log2 e), the constants rounded to fp32 (compiler/glsl/glsl_to_nir.cpp, ir_unop_log and
// ir_unop_exp; M_LOG2E). log2 and exp2 are gallivm's polynomials (gallivm/lp_bld_arit.c,
// lp_build_log2_approx with its edge cases, lp_build_exp2), every step in fp32; their
// multiply-adds (lp_build_mad, llvm.fmuladd) fused where the profile's fma is on.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace oitref::llvmpipe {

// Always inlined, so that a caller built for FMA (a batch kernel) gets the instruction, not a call.
#define OITREF_BUILTIN [[gnu::always_inline]] inline

OITREF_BUILTIN float multiplyAdd(float a, float b, float c, bool fused) { return fused ? __builtin_fmaf(a, b, c) : a * b + c; }

// lp_build_polynomial: odd and even terms apart in powers of x², then odd·x + even.
template <int N>
OITREF_BUILTIN float polynomial(float x, const double (&coefficients)[N], bool fused) {
  const float x2 = x * x;
  float even = 0.0f, odd = 0.0f;
  bool haveEven = false, haveOdd = false;
  for (int i = N; i--;) {
    const float c = float(coefficients[i]);
    float& term = i % 2 == 0 ? even : odd;
    bool& have = i % 2 == 0 ? haveEven : haveOdd;
    term = have ? multiplyAdd(x2, term, c, fused) : c;
    have = true;
  }
  return haveOdd ? multiplyAdd(odd, x, even, fused) : even;
}

// lp_build_exp2's minimax polynomial of 2^x on [0, 1) (EXP_POLY_DEGREE 5).
inline constexpr double kExp2Polynomial[6] = {1.000000000000000000000, 0.693153073200168932794, 0.240153617044375388211,
                                              0.0558263180532956664775, 0.00898934009049466391101,
                                              0.00187757667519147912699};
// lp_build_log2_approx's of log2((1 + √x)/(1 − √x))/√x on [0, 1/9) (LOG_POLY_DEGREE 4), long
// double literals held as doubles, as in Mesa's table.
inline constexpr double kLog2Polynomial[5] = {double(2.88539009343309178325L), double(0.961791550404184197881L),
                                              double(0.577440339438736392009L), double(0.403343858251329912514L),
                                              double(0.406718052498846252698L)};

// lp_build_exp2: x clamped to [−126.99999, 128] (NaN kept), 2^⌊x⌋ from the exponent bits times
// the polynomial of x − ⌊x⌋.
OITREF_BUILTIN float exp2(float x, bool fused) {
  if (!std::isnan(x)) x = std::fmax(-126.99999f, std::fmin(128.0f, x));
  const float whole = std::floor(x);
  const float fraction = x - whole;
  const int32_t exponent = std::isnan(whole) ? INT32_MIN : int32_t(whole);  // fptosi of NaN: cvttps2dq's value
  const float power = std::bit_cast<float>(uint32_t(exponent + 127) << 23);
  return power * polynomial(fraction, kExp2Polynomial, fused);
}

// lp_build_log2_safe: the exponent plus y·P(y²), y = (m − 1)/(m + 1) for the mantissa m in
// [1, 2); +inf for x ≥ +inf, −inf for ±0, NaN below 0 (its ordered comparisons let a NaN through
// the polynomial).
OITREF_BUILTIN float log2(float x, bool fused) {
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  const float exponent = float(int32_t((bits & 0x7f800000u) >> 23) - 127);
  const float mantissa = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);
  const float y = (mantissa - 1.0f) / (mantissa + 1.0f);
  float result = multiplyAdd(y, polynomial(y * y, kLog2Polynomial, fused), exponent, fused);
  if (x >= INFINITY) result = INFINITY;
  if (x == 0.0f) result = -INFINITY;
  if (x < 0.0f) result = NAN;
  return result;
}

// GLSL's log and exp as they reach log2 and exp2 (glsl_to_nir.cpp).
OITREF_BUILTIN float log(float x, bool fused) { return log2(x, fused) * float(1.0 / M_LOG2E); }
OITREF_BUILTIN float exp(float x, bool fused) { return exp2(x * float(M_LOG2E), fused); }

#undef OITREF_BUILTIN

// log and exp of x[0, n) into out (src/core/shader/shader_builtins.cpp): the same bits as the
// functions above, in vector lanes where the CPU can.
void logBatch(const float* x, float* out, int n, bool fused);
void expBatch(const float* x, float* out, int n, bool fused);

}  // namespace oitref::llvmpipe
