// The comparison half of glcheck's blend mode (declared in blend_check.h).
#include <cstdio>
#include <cstring>
#include <map>
#include <ostream>
#include <set>

#include "glcheck/blend_check.h"

namespace oitref::glcheck {
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

BlendCheckSummary compareBlendCases(const std::vector<tools::BlendCase>& cases, const std::vector<GlTexels>& gl,
                                    const Profile& profile, const std::vector<size_t>& lineNumbers, size_t listMismatches,
                                    std::ostream& out) {
  BlendCheckSummary summary;
  std::map<std::string, Tally> byFormat, byEquation, byFactor;
  std::vector<std::string> mismatches;
  for (size_t i = 0; i < cases.size(); ++i) {
    const tools::BlendCase& c = cases[i];
    const tools::BlendOutcome ours = tools::evaluate(c, profile);
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
      m += "    " + tools::blendCaseCsvLine(c) + "\n";
      if (!dstEqual)
        m += "    stored dst  oitref " + texelBitsToString(c.format, ours.dstTexel.data()) + "   GL " +
             texelBitsToString(c.format, gl[i].destination.data()) + "\n";
      m += "    result      oitref " + texelBitsToString(c.format, ours.resultTexel.data()) + "   GL " +
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

}  // namespace oitref::glcheck
