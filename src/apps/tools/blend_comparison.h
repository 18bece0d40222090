// Blend cases against texels recorded elsewhere — a GL driver run by `oitref glcheck blend`, or a
// GPU captured once with oitref-gpu-capture and read back from CSV by `oitref blend --cases`:
// the share of bit-equal stored destinations and blended results per format, equation and factor,
// and the first mismatches with both bit patterns.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "tools/blend_case.h"

namespace oitref::tools {

struct RecordedTexels {
  std::array<uint8_t, 16> destination{}, result{};
};

struct BlendComparison {
  size_t cases = 0, destinationMismatches = 0, resultMismatches = 0;
};

// `lineNumbers[i]` names case i in reports (its CSV line); `other` names the recorded side ("GL").
BlendComparison compareBlendCases(const std::vector<BlendCase>& cases, const std::vector<RecordedTexels>& recorded,
                                  const Profile& profile, const std::vector<size_t>& lineNumbers, size_t listMismatches,
                                  std::ostream& out, const std::string& other = "GL");

// Cases with recorded texels from CSV: the 19 input columns and gpu_dst_bits, gpu_result_bits
// (oitref's dst_bits/result_bits layout), found by the header's names; other columns are ignored.
// Each bad line is reported to `err` with its line and column; returns the number of bad lines.
struct RecordedCases {
  std::vector<BlendCase> cases;
  std::vector<RecordedTexels> texels;
  std::vector<size_t> lines;
};
bool hasRecordedColumns(const std::string& headerLine);
int readRecordedCases(std::istream& in, std::ostream& err, const std::string& sourceName, RecordedCases& out);

}  // namespace oitref::tools
