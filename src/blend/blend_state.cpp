#include "oitref/blend_state.h"

#include <stdexcept>

namespace oitref {
namespace {

constexpr const char* kEquationNames[] = {"add", "subtract", "reverse_subtract", "min", "max"};
constexpr const char* kFactorNames[] = {
    "zero", "one", "src_color", "one_minus_src_color", "dst_color", "one_minus_dst_color",
    "src_alpha", "one_minus_src_alpha", "dst_alpha", "one_minus_dst_alpha", "constant_color",
    "one_minus_constant_color", "constant_alpha", "one_minus_constant_alpha", "src_alpha_saturate"};

template <typename Enum, size_t N>
Enum parseName(const char* const (&names)[N], const std::string& name, const char* what) {
  for (size_t i = 0; i < N; ++i)
    if (name == names[i]) return Enum(i);
  std::string valid;
  for (size_t i = 0; i < N; ++i) valid += std::string(i ? ", " : "") + names[i];
  throw std::invalid_argument(std::string("unknown blend ") + what + " '" + name + "' (valid: " + valid + ")");
}

}  // namespace

const char* toString(BlendEquation e) { return kEquationNames[int(e)]; }
const char* toString(BlendFactor f) { return kFactorNames[int(f)]; }

BlendEquation parseBlendEquation(const std::string& name) {
  return parseName<BlendEquation>(kEquationNames, name, "equation");
}
BlendFactor parseBlendFactor(const std::string& name) { return parseName<BlendFactor>(kFactorNames, name, "factor"); }

std::string BlendState::describe() const {
  std::string mask;
  for (int c = 0; c < 4; ++c) mask += (writeMask & (1 << c)) ? "rgba"[c] : '-';
  if (!enabled) return "blend off mask=" + mask;
  return std::string(toString(equationRgb)) + "," + toString(equationAlpha) + " " + toString(srcRgb) + "," +
         toString(dstRgb) + "," + toString(srcAlpha) + "," + toString(dstAlpha) + " mask=" + mask;
}

}  // namespace oitref
