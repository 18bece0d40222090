#include "oitref/core/blend_state.h"

#include <sstream>
#include <stdexcept>
#include <vector>

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

BlendState parseBlendState(const std::string& equation, const std::string& func, const std::string& equationName,
                           const std::string& funcName) {
  auto splitComma = [](const std::string& s) {
    std::vector<std::string> parts;
    std::istringstream in(s);
    std::string p;
    while (std::getline(in, p, ',')) parts.push_back(p);
    return parts;
  };
  const auto eq = splitComma(equation);
  if (eq.size() != 1 && eq.size() != 2)
    throw std::invalid_argument(equationName + ": expected EQ or EQ_RGB,EQ_ALPHA, got '" + equation + "'");
  const auto fn = splitComma(func);
  if (fn.size() != 2 && fn.size() != 4)
    throw std::invalid_argument(funcName + ": expected SRC,DST or SRC_RGB,DST_RGB,SRC_ALPHA,DST_ALPHA, got '" + func + "'");
  BlendState state;
  state.enabled = true;
  state.equationRgb = parseBlendEquation(eq[0]);
  state.equationAlpha = parseBlendEquation(eq.back());
  state.srcRgb = parseBlendFactor(fn[0]);
  state.dstRgb = parseBlendFactor(fn[1]);
  state.srcAlpha = parseBlendFactor(fn[fn.size() == 4 ? 2 : 0]);
  state.dstAlpha = parseBlendFactor(fn[fn.size() == 4 ? 3 : 1]);
  return state;
}

std::string BlendState::describe() const {
  std::string mask;
  for (int c = 0; c < 4; ++c) mask += (writeMask & (1 << c)) ? "rgba"[c] : '-';
  if (!enabled) return "blend off mask=" + mask;
  return std::string(toString(equationRgb)) + "," + toString(equationAlpha) + " " + toString(srcRgb) + "," +
         toString(dstRgb) + "," + toString(srcAlpha) + "," + toString(dstAlpha) + " mask=" + mask;
}

}  // namespace oitref
