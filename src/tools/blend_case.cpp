#include "tools/blend_case.h"

#include <functional>
#include <istream>
#include <ostream>
#include <sstream>

#include "gpucapture/csv_fields.h"
#include "oitref/blend.h"
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
  bool header = true;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (header) {
      header = false;
      if (line.rfind("format,", 0) == 0) continue;  // the header line
    }
    try {
      visit(lineNo, line, parseBlendCsvLine(line));
    } catch (const BlendCsvError& e) {
      ++bad;
      err << sourceName << ": line " << lineNo << ", column " << e.column << " ("
          << kBlendCsvColumns[std::min(e.column, 19) - 1] << "): " << e.what() << "\n";
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
