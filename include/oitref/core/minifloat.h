// Small floating-point formats: fp16, F11, F10, bfloat16, fp8 and any (exponent, mantissa) pair.
//
// One converter serves every such format, so fp16, the packed F11/F10 channels and user-defined
// minifloats follow literally the same rounding code. Its contract:
//
//  * Rounding::NearestEven (default): the exact value of the fp32 input is rounded to the nearest
//    representable value, ties to the even significand (IEEE 754-2019 §4.3.1
//    roundTiesToEven). Denormals are produced. Finite values that round past the largest finite
//    value become ±inf (IEEE §7.4), unless the format has no inf or saturates (below).
//  * Rounding::TowardZero: truncation of the exact value (IEEE roundTowardZero). Finite values
//    above the largest finite value give the largest finite value; ±inf stays ±inf.
//  * NaN stays NaN: the result is a quiet NaN with the input's sign and the top payload bits
//    (the same bits as the x86 F16C instruction for fp16).
//  * Unsigned formats (F11, F10; GL 4.6 §2.3.4.3–4): negative values, -0 and -inf give +0; any
//    NaN gives +NaN; +inf gives +inf.
//  * finiteOverflowSaturates (F11, F10 per GL 4.6 §2.3.4.3): a finite value that would round past
//    the largest finite value gives the largest finite value, in every rounding mode.
//  * FloatSpecials::FiniteNan (fp8 E4M3 as in the OCP 8-bit spec): no inf; the single NaN
//    pattern is all exponent and mantissa bits set; overflow and ±inf saturate to ±max finite.
//    FloatSpecials::None: every pattern is a finite number; NaN gives +0; overflow saturates.
//  * denormals = false: results that would be denormal after rounding become ±0 (flush to zero),
//    and denormal encodings decode to ±0.
//
// Decoding is exact: every supported format (exponent ≤ 8 bits, mantissa ≤ 23 bits) is a subset
// of fp32.
#pragma once

#include <cstdint>
#include <string>

namespace oitref {

enum class Rounding : uint8_t {
  NearestEven,  // IEEE roundTiesToEven; overflow -> inf (where the format has inf)
  TowardZero,   // IEEE roundTowardZero; finite overflow -> largest finite value
};

enum class FloatSpecials : uint8_t {
  Ieee,       // all-ones exponent encodes inf (mantissa 0) and NaN (mantissa != 0)
  FiniteNan,  // no inf; all-ones exponent and mantissa is the only NaN (OCP fp8 E4M3)
  None,       // no inf, no NaN: every encoding is finite
};

struct MinifloatSpec {
  int exponentBits = 5;   // 2..8
  int mantissaBits = 10;  // 1..23
  bool isSigned = true;
  FloatSpecials specials = FloatSpecials::Ieee;
  bool denormals = true;
  bool finiteOverflowSaturates = false;

  int totalBits() const { return (isSigned ? 1 : 0) + exponentBits + mantissaBits; }
  int bias() const { return (1 << (exponentBits - 1)) - 1; }
  bool operator==(const MinifloatSpec&) const = default;

  // "e5m10", "e5m6u", "e4m3fn", with "_ftz" when denormals are flushed, "_sat" when finite
  // overflow saturates.
  std::string name() const;
  // Throws std::invalid_argument naming the bad field when the spec is outside the supported
  // range (exponent 2..8, mantissa 1..23, FiniteNan needs a signed format).
  void validate() const;
};

// Well-known specs.
inline constexpr MinifloatSpec kHalfSpec{5, 10, true, FloatSpecials::Ieee, true, false};
inline constexpr MinifloatSpec kFloat11Spec{5, 6, false, FloatSpecials::Ieee, true, true};
inline constexpr MinifloatSpec kFloat10Spec{5, 5, false, FloatSpecials::Ieee, true, true};
inline constexpr MinifloatSpec kBfloat16Spec{8, 7, true, FloatSpecials::Ieee, true, false};
inline constexpr MinifloatSpec kFp8E5M2Spec{5, 2, true, FloatSpecials::Ieee, true, false};
inline constexpr MinifloatSpec kFp8E4M3Spec{4, 3, true, FloatSpecials::FiniteNan, true, false};
inline constexpr MinifloatSpec kFp24Spec{7, 16, true, FloatSpecials::Ieee, true, false};

// fp32 -> the format's bits (in the low totalBits() bits), by the contract above.
uint32_t encodeMinifloat(float value, const MinifloatSpec& spec, Rounding rounding);
// The format's bits -> its exact value as fp32.
float decodeMinifloat(uint32_t bits, const MinifloatSpec& spec);
// The largest finite value of the format.
float largestFiniteMinifloat(const MinifloatSpec& spec);

// Parses a spec string "e<E>m<M>[u][fn|nonan][_ftz][_sat]", e.g. "e8m7" (bfloat16), "e4m3fn",
// "e5m2", "e7m16" (fp24), "e5m6u_sat". Throws std::invalid_argument with the reason.
MinifloatSpec parseMinifloatSpec(const std::string& text);

}  // namespace oitref
