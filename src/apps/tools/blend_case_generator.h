// Random blend cases that stress the extremes of each format: exact rounding ties, fp16 denormal
// edges, 65504 / 65520, the F11/F10 maxima, out-of-range values for UNORM targets, tiny and huge
// values, and — only when asked — NaN and infinities. Cases come in groups that share a format,
// a blend state and a constant, so a GL driver can draw each group with one state change.
// The same seed gives the same cases on every platform (util::SeededRandom).
#pragma once

#include <cstdint>
#include <vector>

#include "tools/blend_case.h"

namespace oitref::tools {

struct BlendCaseGeneratorOptions {
  size_t count = 20000;
  uint32_t seed = 1;
  bool nonFinite = false;        // also NaN and ±inf among the values
  size_t groupSize = 64;         // cases per (format, blend state, constant)
  std::vector<Format> formats;   // empty: the formats GL shares with oitref (glFormatNames())
};

std::vector<BlendCase> generateBlendCases(const BlendCaseGeneratorOptions& options);

// The built-in formats that are also GL colour-renderable formats (every one but minifloats).
std::vector<Format> glSharedFormats();

}  // namespace oitref::tools
