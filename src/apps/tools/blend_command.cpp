// `oitref blend`: the blend calculator (single case or CSV batch).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <sstream>

#include "tools/blend_case.h"
#include "tools/blend_comparison.h"
#include "tools/commands.h"
#include "tools/number_parse.h"

namespace oitref::tools {
namespace {

struct BlendOptions {
  std::string format = "rgba8", equation = "add", func = "one,zero", constant = "0,0,0,0";
  std::string dst = "0,0,0,0", src = "0,0,0,0", cases, profile = "exact";
  size_t list = 20;
};

std::string valuesText(const glm::vec4& v, int channels) {
  std::string hex, dec;
  char buf[40];
  for (int i = 0; i < channels; ++i) {
    hex += (i ? " " : "") + hexFloat(v[i]);
    std::snprintf(buf, sizeof buf, "%s%.9g", i ? " " : "", double(v[i]));
    dec += buf;
  }
  return hex + "  (" + dec + ")";
}

BlendCase caseFromOptions(const BlendOptions& o) {
  BlendCase c;
  c.format = parseFormat(o.format);
  c.state = parseBlendState(o.equation, o.func, "--equation", "--func");
  c.constant = parseVec4(o.constant, "--constant");
  c.destination = parseVec4(o.dst, "--dst");
  c.source = parseVec4(o.src, "--src");
  return c;
}

int runSingle(const BlendOptions& o) {
  const Profile profile = parseProfile(o.profile);
  const BlendCase c = caseFromOptions(o);
  const BlendOutcome r = evaluate(c, profile);
  const int ch = c.format.channels;
  std::cout << "format       " << c.format.name() << "\n"
            << "blend        " << c.state.describe() << "\n"
            << "profile      " << profile.describe() << "\n"
            << "constant     " << valuesText(c.constant, 4) << "\n"
            << "source       " << valuesText(c.source, 4) << "\n"
            << "destination  bits " << texelBitsToString(c.format, r.dstTexel.data()) << "  value "
            << valuesText(r.dstStored, ch) << "\n"
            << "result       bits " << texelBitsToString(c.format, r.resultTexel.data()) << "  value "
            << valuesText(r.result, ch) << "\n";
  return 0;
}

int runBatch(const BlendOptions& o) {
  const Profile profile = parseProfile(o.profile);
  std::unique_ptr<std::istream> file;
  std::istream* in = &std::cin;
  if (o.cases != "-") {
    std::error_code ec;
    if (std::filesystem::is_directory(o.cases, ec)) {
      std::cerr << "oitref blend: '" << o.cases << "' is a folder: --cases takes a CSV file ('-' for stdin)\n";
      return 2;
    }
    file = std::make_unique<std::ifstream>(o.cases);
    if (!*file) {
      std::cerr << "oitref blend: cannot read '" << o.cases << "'\n";
      return 2;
    }
    in = file.get();
  }
  const std::string name = o.cases == "-" ? "<stdin>" : o.cases;
  std::string text((std::istreambuf_iterator<char>(*in)), std::istreambuf_iterator<char>());
  std::istringstream csv(text);
  if (hasRecordedColumns(text.substr(0, text.find('\n')))) {
    // Recorded GPU texels (oitref-gpu-capture): compare instead of printing results.
    RecordedCases recorded;
    const int bad = readRecordedCases(csv, std::cerr, name, recorded);
    std::cout << recorded.cases.size() << " cases with recorded texels from " << name << "\n";
    const BlendComparison s =
        compareBlendCases(recorded.cases, recorded.texels, profile, recorded.lines, o.list, std::cout, "GPU");
    if (bad) std::cerr << "oitref blend: " << bad << " bad line(s) skipped\n";
    return bad ? 2 : s.destinationMismatches || s.resultMismatches ? 1 : 0;  // an error before a difference
  }
  const int bad = runBlendCsv(csv, std::cout, std::cerr, profile, name);
  if (bad) std::cerr << "oitref blend: " << bad << " bad line(s) skipped\n";
  return bad ? 2 : 0;
}

}  // namespace

void addBlendCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<BlendOptions>();
  CLI::App* cmd = app.add_subcommand("blend", "Blend one source into one stored destination, exactly as a render target would");
  cmd->add_option("--format", o->format, "Target format: rgba8, rgba16f, r11g11b10f, rgba:e8m7, ...")->capture_default_str();
  cmd->add_option("--equation", o->equation, "EQ or EQ_RGB,EQ_ALPHA (add, subtract, reverse_subtract, min, max)")->capture_default_str();
  cmd->add_option("--func", o->func, "SRC,DST or SRC_RGB,DST_RGB,SRC_ALPHA,DST_ALPHA factors")->capture_default_str();
  cmd->add_option("--constant", o->constant, "Blend constant r,g,b,a")->capture_default_str();
  cmd->add_option("--dst", o->dst, "Destination r,g,b,a (stored first, converted to the format)")->capture_default_str();
  cmd->add_option("--src", o->src, "Source r,g,b,a (fp32 fragment output)")->capture_default_str();
  nonEmptyPath(cmd->add_option("--cases", o->cases,
                  "CSV file of cases ('-' for stdin); results as CSV on stdout, or, when the file has gpu_dst_bits and "
                  "gpu_result_bits columns (oitref-gpu-capture), the share of bit-equal texels and exit status 1 on any difference"));
  cmd->add_option("--list", o->list, "With recorded GPU texels: how many mismatches to list")->capture_default_str();
  addProfileOption(cmd, o->profile);
  cmd->callback([o, &exitCode] {
    exitCode = runReportingErrors("blend", [&] {
      return o->cases.empty() ? runSingle(*o) : runBatch(*o);
    });
  });
}

}  // namespace oitref::tools
