// The rule a colour given in a scene obeys, wherever it comes from — an object's color_override
// or a mesh's vertex colours (PLY, OBJ, glTF …): every channel a finite number, none negative,
// alpha at most 1 (a straight colour; RGB above 1 is an HDR colour and allowed).
#pragma once

#include <cmath>

#include <glm/vec4.hpp>

namespace oitref::detail {

// What is wrong with channel `channel` of c, or nullptr; `channel` is the first bad one.
inline const char* colourProblem(const glm::vec4& c, int& channel) {
  for (channel = 0; channel < 4; ++channel) {
    if (!std::isfinite(c[channel])) return "colour components must be finite";
    if (c[channel] < 0.0f) return "colour components must not be negative";
  }
  channel = 3;
  return c.a > 1.0f ? "alpha must lie in [0, 1]" : nullptr;
}

}  // namespace oitref::detail
