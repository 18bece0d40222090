#include "tools/blend_case.h"

#include <algorithm>
#include <functional>
#include <istream>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "gpucapture/csv_fields.h"
#include "oitref/core/blend.h"
#include "tools/number_parse.h"

namespace oitref::tools {

const char* const kBlendCsvColumns[19] = {"format",  "eq_rgb",  "eq_alpha", "src_rgb", "dst_rgb", "src_alpha", "dst_alpha",
                                          "const_r", "const_g", "const_b",  "const_a", "dst_r",   "dst_g",     "dst_b",
                                          "dst_a",   "src_r",   "src_g",    "src_b",   "src_a"};

BlendOutcome evaluate(const BlendCase& c, const Profile& profile) {
  BlendOutcome o;
  encodeTexel(c.format, c.destination, profile, o.dstTexel.data());
  o.dstStored = decodeTexel(c.format, o.dstTexel.data());
  o.resultTexel = o.dstTexel;
  blendIntoTexel(c.format, c.state, c.constant, profile, c.source, o.resultTexel.data());
  o.result = decodeTexel(c.format, o.resultTexel.data());
  return o;
}

std::string blendCsvHeader(bool withResults) {
  std::string h;
  for (int i = 0; i < 19; ++i) h += std::string(i ? "," : "") + kBlendCsvColumns[i];
  if (withResults) h += ",dst_bits,result_bits,result_r,result_g,result_b,result_a";
  return h;
}

BlendCase parseBlendCsvLine(const std::string& line) {
  const std::vector<std::string> f = splitCsvFields(line);
  if (f.size() != 19)
    throw BlendCsvError(int(std::min<size_t>(f.size(), 19)) + (f.size() < 19 ? 1 : 0),
                        "expected 19 fields, found " + std::to_string(f.size()));
  BlendCase c;
  auto guard = [&](int col, auto&& parse) {
    try {
      parse();
    } catch (const std::invalid_argument& e) {
      throw BlendCsvError(col, e.what());
    }
  };
  guard(1, [&] { c.format = parseFormat(f[0]); });
  c.state.enabled = true;
  guard(2, [&] { c.state.equationRgb = parseBlendEquation(f[1]); });
  guard(3, [&] { c.state.equationAlpha = parseBlendEquation(f[2]); });
  guard(4, [&] { c.state.srcRgb = parseBlendFactor(f[3]); });
  guard(5, [&] { c.state.dstRgb = parseBlendFactor(f[4]); });
  guard(6, [&] { c.state.srcAlpha = parseBlendFactor(f[5]); });
  guard(7, [&] { c.state.dstAlpha = parseBlendFactor(f[6]); });
  glm::vec4* targets[3] = {&c.constant, &c.destination, &c.source};
  for (int i = 0; i < 12; ++i) {
    const auto v = parseFloatExact(f[size_t(7 + i)]);
    if (!v) throw BlendCsvError(8 + i, "'" + f[size_t(7 + i)] + "' is not a number (decimal, hex float, nan, inf)");
    (*targets[i / 4])[i % 4] = *v;
  }
  return c;
}

std::string blendCaseCsvLine(const BlendCase& c) {
  std::string line = c.format.name() + "," + toString(c.state.equationRgb) + "," + toString(c.state.equationAlpha) + "," +
                     toString(c.state.srcRgb) + "," + toString(c.state.dstRgb) + "," + toString(c.state.srcAlpha) + "," +
                     toString(c.state.dstAlpha);
  for (const glm::vec4* v : {&c.constant, &c.destination, &c.source})
    for (int i = 0; i < 4; ++i) line += "," + hexFloat((*v)[i]);
  return line;
}

std::string formatBlendCsvLine(const std::string& inputLine, const BlendCase& c, const BlendOutcome& o) {
  std::string line = inputLine;
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  line += "," + texelBitsToString(c.format, o.dstTexel.data()) + "," + texelBitsToString(c.format, o.resultTexel.data());
  for (int i = 0; i < 4; ++i) line += "," + hexFloat(o.result[i]);
  return line;
}

int forEachBlendCsvCase(std::istream& in, std::ostream& err, const std::string& sourceName,
                        const std::function<void(int, const std::string&, const BlendCase&)>& visit) {
  std::string line;
  int lineNo = 0, bad = 0;
  bool first = true;
  // A header (a first line with a field "format", which no case has) says where each column is:
  // the columns are read by name, in any order (fileColumn[i]: the file's column of
  // kBlendCsvColumns[i]).
  std::vector<size_t> fileColumn;
  size_t headerFields = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (first) {
      first = false;
      const std::vector<std::string> header = splitCsvFields(line);
      if (std::find(header.begin(), header.end(), "format") != header.end()) {
        headerFields = header.size();
        for (const char* name : kBlendCsvColumns) {
          size_t j = 0;
          while (j < header.size() && header[j] != name) ++j;
          if (j == header.size())
            throw std::invalid_argument(sourceName + ": line " + std::to_string(lineNo) + ": the header has no column '" +
                                        name + "'");
          fileColumn.push_back(j);
        }
        bool inOrder = true;
        for (size_t i = 0; i < fileColumn.size(); ++i) inOrder = inOrder && fileColumn[i] == i;
        if (inOrder) fileColumn.clear();
        continue;
      }
    }
    std::string inputs = line;
    if (!fileColumn.empty()) {  // the columns in kBlendCsvColumns' order
      const std::vector<std::string> f = splitCsvFields(line);
      if (f.size() != headerFields) {
        ++bad;
        err << sourceName << ": line " << lineNo << ": " << f.size() << " fields where the header has " << headerFields << "\n";
        continue;
      }
      inputs.clear();
      for (size_t i = 0; i < fileColumn.size(); ++i) inputs += (i ? "," : "") + (fileColumn[i] < f.size() ? f[fileColumn[i]] : "");
    }
    try {
      visit(lineNo, line, parseBlendCsvLine(inputs));
    } catch (const BlendCsvError& e) {
      ++bad;
      const int column = std::min(e.column, 19);
      err << sourceName << ": line " << lineNo << ", column "
          << (fileColumn.empty() ? size_t(e.column) : fileColumn[size_t(column) - 1] + 1) << " ("
          << kBlendCsvColumns[column - 1] << "): " << e.what() << "\n";
    }
  }
  return bad;
}

int runBlendCsv(std::istream& in, std::ostream& out, std::ostream& err, const Profile& profile,
                const std::string& sourceName) {
  out << blendCsvHeader(true) << "\n";
  return forEachBlendCsvCase(in, err, sourceName, [&](int, const std::string& line, const BlendCase& c) {
    out << formatBlendCsvLine(line, c, evaluate(c, profile)) << "\n";
  });
}

}  // namespace oitref::tools
