// One blend test case: a format, a blend state and constant, a destination to store and a source
// to blend. `oitref blend` evaluates single cases and CSV batches; glcheck reuses the CSV format.
//
// CSV columns (header line first, one case per line):
//   format,eq_rgb,eq_alpha,src_rgb,dst_rgb,src_alpha,dst_alpha,const_r,const_g,const_b,const_a,
//   dst_r,dst_g,dst_b,dst_a,src_r,src_g,src_b,src_a
// Output repeats them and adds dst_bits,result_bits,result_r,result_g,result_b,result_a.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "oitref/core/blend_state.h"
#include "oitref/core/format.h"
#include "oitref/core/profile.h"

namespace oitref::tools {

struct BlendCase {
  Format format;
  BlendState state;  // enabled
  glm::vec4 constant{0.0f}, destination{0.0f}, source{0.0f};
};

struct BlendOutcome {
  std::array<uint8_t, 16> dstTexel{}, resultTexel{};
  glm::vec4 dstStored{0.0f}, result{0.0f};  // decoded
};

BlendOutcome evaluate(const BlendCase& c, const Profile& profile);

extern const char* const kBlendCsvColumns[19];
std::string blendCsvHeader(bool withResults);

// Parses one CSV line. Throws BlendCsvError with the 1-based column of the first bad field.
struct BlendCsvError : std::invalid_argument {
  int column;
  BlendCsvError(int col, const std::string& what) : std::invalid_argument(what), column(col) {}
};
BlendCase parseBlendCsvLine(const std::string& line);
// The case as a CSV line (the 19 input columns), every number as an exact hex float.
std::string blendCaseCsvLine(const BlendCase& c);
// The input columns of the case, then the outcome's columns.
std::string formatBlendCsvLine(const std::string& inputLine, const BlendCase& c, const BlendOutcome& o);

// Parses a CSV stream (header line optional, blank lines skipped) and calls `visit(line number,
// line, case)` for each good line; reports each bad line to `err` as "SOURCE: line N, column C
// (name): reason". Returns the number of bad lines. With a header (a first line with a field
// "format") the columns are read by name, in any order; a header without one of the 19 input
// columns throws std::invalid_argument naming it. Without one they are read in kBlendCsvColumns'
// order.
int forEachBlendCsvCase(std::istream& in, std::ostream& err, const std::string& sourceName,
                        const std::function<void(int, const std::string&, const BlendCase&)>& visit);

// Runs a whole CSV stream: results to `out`, one error per bad line to `err` ("line N, column C
// (name): reason"). Returns the number of bad lines.
int runBlendCsv(std::istream& in, std::ostream& out, std::ostream& err, const Profile& profile,
                const std::string& sourceName);

}  // namespace oitref::tools
