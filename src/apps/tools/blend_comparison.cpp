#include "tools/blend_comparison.h"

#include "gpucapture/csv_fields.h"

#include <cstdio>
#include <cstring>
#include <istream>
#include <map>
#include <ostream>
#include <set>
#include <sstream>

namespace oitref::tools {
namespace {

struct Tally {
  size_t cases = 0, destinationEqual = 0, resultEqual = 0;
  void add(bool dst, bool result) {
    ++cases;
    destinationEqual += dst;
    resultEqual += result;
  }
};

std::string percent(size_t part, size_t whole) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f%%", whole ? 100.0 * double(part) / double(whole) : 100.0);
  return buf;
}

void printTable(std::ostream& out, const char* title, const std::map<std::string, Tally>& rows) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%-24s %8s %18s %18s\n", title, "cases", "dst bit-equal", "result bit-equal");
  out << buf;
  for (const auto& [name, t] : rows) {
    std::snprintf(buf, sizeof buf, "%-24s %8zu %18s %18s\n", name.c_str(), t.cases, percent(t.destinationEqual, t.cases).c_str(),
                  percent(t.resultEqual, t.cases).c_str());
    out << buf;
  }
  out << "\n";
}

}  // namespace

BlendComparison compareBlendCases(const std::vector<BlendCase>& cases, const std::vector<RecordedTexels>& gl,
                                  const Profile& profile, const std::vector<size_t>& lineNumbers, size_t listMismatches,
                                  std::ostream& out, const std::string& other) {
  BlendComparison summary;
  std::map<std::string, Tally> byFormat, byEquation, byFactor;
  std::vector<std::string> mismatches;
  for (size_t i = 0; i < cases.size(); ++i) {
    const BlendCase& c = cases[i];
    const BlendOutcome ours = evaluate(c, profile);
    const size_t bytes = size_t(c.format.bytesPerTexel());
    const bool dstEqual = std::memcmp(ours.dstTexel.data(), gl[i].destination.data(), bytes) == 0;
    const bool resultEqual = std::memcmp(ours.resultTexel.data(), gl[i].result.data(), bytes) == 0;
    ++summary.cases;
    summary.destinationMismatches += !dstEqual;
    summary.resultMismatches += !resultEqual;
    byFormat[c.format.name()].add(dstEqual, resultEqual);
    for (BlendEquation e : std::set<BlendEquation>{c.state.equationRgb, c.state.equationAlpha})
      byEquation[toString(e)].add(dstEqual, resultEqual);
    for (BlendFactor f : std::set<BlendFactor>{c.state.srcRgb, c.state.dstRgb, c.state.srcAlpha, c.state.dstAlpha})
      byFactor[toString(f)].add(dstEqual, resultEqual);
    if ((!dstEqual || !resultEqual) && mismatches.size() < listMismatches) {
      std::string m = "  case " + std::to_string(lineNumbers.empty() ? i + 1 : lineNumbers[i]) + ": " + c.format.name() + " " +
                      c.state.describe() + "\n";
      m += "    " + blendCaseCsvLine(c) + "\n";
      if (!dstEqual)
        m += "    stored dst  oitref " + texelBitsToString(c.format, ours.dstTexel.data()) + "   " + other + " " +
             texelBitsToString(c.format, gl[i].destination.data()) + "\n";
      m += "    result      oitref " + texelBitsToString(c.format, ours.resultTexel.data()) + "   " + other + " " +
           texelBitsToString(c.format, gl[i].result.data()) + "\n";
      mismatches.push_back(m);
    }
  }
  out << "profile " << profile.describe() << "\n\n";
  printTable(out, "format", byFormat);
  printTable(out, "equation (rgb or alpha)", byEquation);
  printTable(out, "factor (any of the four)", byFactor);
  out << "all: " << summary.cases << " cases, stored destinations bit-equal "
      << percent(summary.cases - summary.destinationMismatches, summary.cases) << ", blended results bit-equal "
      << percent(summary.cases - summary.resultMismatches, summary.cases) << "\n";
  if (!mismatches.empty()) {
    out << "first " << mismatches.size() << " mismatch(es):\n";
    for (const auto& m : mismatches) out << m;
  }
  return summary;
}

namespace {

// Inverse of texelBitsToString: hex words per channel, or one word for packed formats.
bool parseTexelBits(const Format& f, const std::string& text, uint8_t* texel) {
  std::istringstream in(text);
  std::string word;
  const int words = f.isPacked() ? 1 : f.channels, bytes = f.isPacked() ? 4 : f.bytesPerChannel();
  for (int c = 0; c < words; ++c) {
    if (!(in >> word) || word.size() != size_t(2 * bytes) || word.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
      return false;
    const uint32_t v = uint32_t(std::stoul(word, nullptr, 16));
    std::memcpy(texel + c * bytes, &v, size_t(bytes));
  }
  return !(in >> word);
}

}  // namespace

bool hasRecordedColumns(const std::string& headerLine) {
  const auto h = splitCsvFields(headerLine);
  bool dst = false, result = false;
  for (const std::string& s : h) {
    dst |= s == "gpu_dst_bits";
    result |= s == "gpu_result_bits";
  }
  return dst && result;
}

int readRecordedCases(std::istream& in, std::ostream& err, const std::string& sourceName, RecordedCases& out) {
  std::string line;
  if (!std::getline(in, line)) {
    err << sourceName << ": empty file\n";
    return 1;
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::vector<std::string> header = splitCsvFields(line);
  auto column = [&](const std::string& name) {
    for (size_t j = 0; j < header.size(); ++j)
      if (header[j] == name) return j;
    throw std::invalid_argument(sourceName + ": the header has no column '" + name + "'");
  };
  size_t input[19];
  for (int i = 0; i < 19; ++i) input[i] = column(kBlendCsvColumns[i]);
  const size_t dstColumn = column("gpu_dst_bits"), resultColumn = column("gpu_result_bits");
  int bad = 0;
  size_t lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> f = splitCsvFields(line);
    auto report = [&](size_t col, const std::string& what) {
      ++bad;
      err << sourceName << ": line " << lineNo << ", column " << col + 1 << " ("
          << (col < header.size() ? header[col] : std::string("?")) << "): " << what << "\n";
    };
    if (f.size() != header.size()) {
      report(std::min(f.size(), header.size()), std::to_string(f.size()) + " fields where the header has " +
                                                    std::to_string(header.size()));
      continue;
    }
    std::string inputs;
    for (int i = 0; i < 19; ++i) inputs += (i ? "," : "") + f[input[i]];
    BlendCase c;
    try {
      c = parseBlendCsvLine(inputs);
    } catch (const BlendCsvError& e) {
      report(input[e.column - 1], e.what());
      continue;
    }
    RecordedTexels t;
    if (!parseTexelBits(c.format, f[dstColumn], t.destination.data())) {
      report(dstColumn, "'" + f[dstColumn] + "' is not a " + c.format.name() + " texel in hex");
      continue;
    }
    if (!parseTexelBits(c.format, f[resultColumn], t.result.data())) {
      report(resultColumn, "'" + f[resultColumn] + "' is not a " + c.format.name() + " texel in hex");
      continue;
    }
    out.cases.push_back(c);
    out.texels.push_back(t);
    out.lines.push_back(lineNo);
  }
  return bad;
}

}  // namespace oitref::tools
