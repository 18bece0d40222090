// The one fp32 -> small-float converter. See include/oitref/core/minifloat.h for the contract.
//
// Method: an fp32 value is exactly m·2^e with an integer m < 2^24. The target format places its
// unit in the last place (ulp) at 2^(te - M), te being the value's exponent clamped below at the
// format's minimum normal exponent (so denormals fall out of the same arithmetic). We shift m to
// that ulp with integer arithmetic, keeping the discarded bits, and round from them: nothing is
// ever rounded twice.
#include "oitref/core/minifloat.h"

#include <bit>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <string_view>

namespace oitref {
namespace {

uint32_t floatBits(float f) { return std::bit_cast<uint32_t>(f); }

struct Layout {
  int E, M;
  uint32_t mantMask, expAllOnes, signBit;
  int bias, emin;
  explicit Layout(const MinifloatSpec& s)
      : E(s.exponentBits),
        M(s.mantissaBits),
        mantMask((1u << s.mantissaBits) - 1),
        expAllOnes((1u << s.exponentBits) - 1),
        signBit(s.isSigned ? 1u << (s.exponentBits + s.mantissaBits) : 0),
        bias(s.bias()),
        emin(1 - s.bias()) {}
  uint32_t maxFiniteBits(const MinifloatSpec& s) const {
    switch (s.specials) {
      case FloatSpecials::Ieee: return ((expAllOnes - 1) << M) | mantMask;
      case FloatSpecials::FiniteNan: return (expAllOnes << M) | (mantMask - 1);
      case FloatSpecials::None: return (expAllOnes << M) | mantMask;
    }
    return 0;
  }
};

}  // namespace

std::string MinifloatSpec::name() const {
  std::string n = "e" + std::to_string(exponentBits) + "m" + std::to_string(mantissaBits);
  if (!isSigned) n += "u";
  if (specials == FloatSpecials::FiniteNan) n += "fn";
  if (specials == FloatSpecials::None) n += "nonan";
  if (!denormals) n += "_ftz";
  if (finiteOverflowSaturates) n += "_sat";
  return n;
}

void MinifloatSpec::validate() const {
  if (exponentBits < 2 || exponentBits > 8)
    throw std::invalid_argument("minifloat exponent bits must be 2..8, got " + std::to_string(exponentBits));
  if (mantissaBits < 1 || mantissaBits > 23)
    throw std::invalid_argument("minifloat mantissa bits must be 1..23, got " + std::to_string(mantissaBits));
  if (specials == FloatSpecials::FiniteNan && !isSigned)
    throw std::invalid_argument("minifloat 'fn' (finite + single NaN) needs a signed format");
}

uint32_t encodeMinifloat(float value, const MinifloatSpec& spec, Rounding rounding) {
  const Layout L(spec);
  const uint32_t u = floatBits(value);
  const bool negative = (u >> 31) != 0;
  const uint32_t absBits = u & 0x7fffffffu;
  const uint32_t sign = negative ? L.signBit : 0;
  const uint32_t maxFinite = L.maxFiniteBits(spec);

  if (absBits > 0x7f800000u) {  // NaN
    switch (spec.specials) {
      case FloatSpecials::Ieee: {
        const uint32_t payload = (absBits & 0x7fffffu) >> (23 - L.M);
        return sign | (L.expAllOnes << L.M) | (1u << (L.M - 1)) | payload;
      }
      case FloatSpecials::FiniteNan: return sign | (L.expAllOnes << L.M) | L.mantMask;
      case FloatSpecials::None: return 0;
    }
  }
  if (!spec.isSigned && negative) return 0;  // negatives, -0, -inf -> +0 (GL §2.3.4.3)
  if (absBits == 0x7f800000u) {              // ±inf
    if (spec.specials == FloatSpecials::Ieee) return sign | (L.expAllOnes << L.M);
    return sign | maxFinite;
  }
  if (absBits == 0) return sign;

  // value = m · 2^e exactly.
  const uint32_t exp32 = absBits >> 23;
  uint64_t m = exp32 ? ((absBits & 0x7fffffu) | 0x800000u) : (absBits & 0x7fffffu);
  const int e = exp32 ? int(exp32) - 150 : -149;
  const int lead = e + (63 - std::countl_zero(m));  // floor(log2(value))
  int te = lead > L.emin ? lead : L.emin;
  const int shift = (te - L.M) - e;  // how far the ulp lies above m's unit

  uint64_t q;
  if (shift <= 0) {
    q = m << -shift;  // exact: the format has at least the value's precision here
  } else if (shift > 40) {
    q = 0;  // m < 2^24 < half an ulp: rounds to zero in both modes
  } else {
    q = m >> shift;
    const uint64_t rem = m & ((uint64_t(1) << shift) - 1);
    const uint64_t half = uint64_t(1) << (shift - 1);
    if (rounding == Rounding::NearestEven && (rem > half || (rem == half && (q & 1)))) ++q;
  }
  if (q >> (L.M + 1)) {  // rounding carried into a new binade
    q >>= 1;
    ++te;
  }
  if (q == 0) return sign;
  if (q <= L.mantMask) {  // denormal (te == emin)
    return spec.denormals ? (sign | uint32_t(q)) : sign;
  }
  const uint32_t biased = uint32_t(te + L.bias);
  const uint32_t bits = (biased << L.M) | (uint32_t(q) & L.mantMask);
  const bool overflow = biased > L.expAllOnes || bits > maxFinite;
  if (!overflow) return sign | bits;
  const bool toInf = spec.specials == FloatSpecials::Ieee && rounding == Rounding::NearestEven &&
                     !spec.finiteOverflowSaturates;
  return sign | (toInf ? (L.expAllOnes << L.M) : maxFinite);
}

float decodeMinifloat(uint32_t bits, const MinifloatSpec& spec) {
  const Layout L(spec);
  const bool negative = (bits & L.signBit) != 0;
  const uint32_t biased = (bits >> L.M) & L.expAllOnes;
  const uint32_t mant = bits & L.mantMask;
  const uint32_t signF = negative ? 0x80000000u : 0;
  if (spec.specials == FloatSpecials::Ieee && biased == L.expAllOnes) {
    if (mant == 0) return std::bit_cast<float>(signF | 0x7f800000u);
    return std::bit_cast<float>(signF | 0x7fc00000u | (mant << (23 - L.M)));
  }
  if (spec.specials == FloatSpecials::FiniteNan && biased == L.expAllOnes && mant == L.mantMask)
    return std::bit_cast<float>(signF | 0x7fc00000u);
  float magnitude;
  if (biased == 0) {
    magnitude = spec.denormals ? std::ldexp(float(mant), L.emin - L.M) : 0.0f;
  } else {
    magnitude = std::ldexp(float(mant | (1u << L.M)), int(biased) - L.bias - L.M);
  }
  return negative ? -magnitude : magnitude;
}

float largestFiniteMinifloat(const MinifloatSpec& spec) {
  return decodeMinifloat(Layout(spec).maxFiniteBits(spec), spec);
}

MinifloatSpec parseMinifloatSpec(const std::string& text) {
  MinifloatSpec s;
  s.specials = FloatSpecials::Ieee;
  s.isSigned = true;
  s.denormals = true;
  s.finiteOverflowSaturates = false;
  size_t pos = 0;
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument("bad minifloat spec '" + text + "': " + why +
                                " (expected e<E>m<M>[u][fn|nonan][_ftz][_sat], e.g. e8m7, e4m3fn)");
  };
  // Digits read here, not by std::stoi, which throws std::out_of_range past INT_MAX (the fuzzer's
  // e3333…3): any count over 999 bits is refused as too large, naming its position.
  auto readInt = [&]() {
    const size_t start = pos;
    int value = 0;
    for (; pos < text.size() && std::isdigit(static_cast<unsigned char>(text[pos])); ++pos) {
      if (value > 99) fail("the number at position " + std::to_string(start) + " is too large");
      value = value * 10 + (text[pos] - '0');
    }
    if (start == pos) fail("missing number at position " + std::to_string(start));
    return value;
  };
  if (pos >= text.size() || text[pos] != 'e') fail("must start with 'e'");
  ++pos;
  s.exponentBits = readInt();
  if (pos >= text.size() || text[pos] != 'm') fail("missing 'm'");
  ++pos;
  s.mantissaBits = readInt();
  std::string_view rest = std::string_view(text).substr(pos);
  auto eat = [&](std::string_view token) {
    if (rest.substr(0, token.size()) != token) return false;
    rest.remove_prefix(token.size());
    return true;
  };
  if (eat("u")) s.isSigned = false;
  if (eat("fn")) s.specials = FloatSpecials::FiniteNan;
  else if (eat("nonan")) s.specials = FloatSpecials::None;
  if (eat("_ftz")) s.denormals = false;
  if (eat("_sat")) s.finiteOverflowSaturates = true;
  if (!rest.empty()) fail("unexpected '" + std::string(rest) + "'");
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
  return s;
}

}  // namespace oitref
