// `oitref glcheck`: checks oitref against a real OpenGL driver (headless, through EGL).
//   glcheck blend  the blend cases of `oitref blend --cases`, or generated ones, bit for bit
//   glcheck scene  scenes rendered by the GL version of each method, against `oitref render`
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "glcheck/blend_check.h"
#include "glcheck/gl_context.h"
#include "glcheck/gl_methods.h"
#include "glcheck/scene_check.h"
#include "gpucapture/gl_trace.h"
#include "tools/blend_case_generator.h"
#include "tools/command_line.h"
#include "tools/commands.h"
#include "oitref/oit/image_io.h"
#include "tools/number_parse.h"
#include "tools/suite.h"

namespace oitref::glcheck {
namespace {

struct BlendCheckOptions {
  std::string cases, writeCases, results, profile = "llvmpipe";
  size_t generate = 20000, list = 20;
  uint32_t seed = 1;
  bool nonFinite = false;
};

void printDriver(const GlContext& context) {
  std::cout << "GL renderer  " << context.renderer() << "\n"
            << "GL version   " << context.version() << "\n"
            << "GL vendor    " << context.vendor() << "  (EGL " << context.platform() << " platform)\n";
}

// Reads a CSV of cases; bad lines are reported and skipped (as `oitref blend --cases` does).
size_t readCases(const std::string& path, std::vector<tools::BlendCase>& cases, std::vector<size_t>& lines) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  return size_t(tools::forEachBlendCsvCase(in, std::cerr, path, [&](int lineNo, const std::string&, const tools::BlendCase& c) {
    cases.push_back(c);
    lines.push_back(size_t(lineNo));
  }));
}

// Every case with GL's and oitref's stored destination and result bits, as CSV.
void writeResults(const std::string& path, const std::vector<tools::BlendCase>& cases, const std::vector<tools::RecordedTexels>& gl,
                  const Profile& profile) {
  std::ostringstream w;
  w << tools::blendCsvHeader(false) << ",gl_dst_bits,gl_result_bits,oitref_dst_bits,oitref_result_bits,equal\n";
  for (size_t i = 0; i < cases.size(); ++i) {
    const tools::BlendCase& c = cases[i];
    const tools::BlendOutcome ours = tools::evaluate(c, profile);
    const std::string glDst = texelBitsToString(c.format, gl[i].destination.data());
    const std::string glResult = texelBitsToString(c.format, gl[i].result.data());
    const std::string ourDst = texelBitsToString(c.format, ours.dstTexel.data());
    const std::string ourResult = texelBitsToString(c.format, ours.resultTexel.data());
    w << tools::blendCaseCsvLine(c) << "," << glDst << "," << glResult << "," << ourDst << "," << ourResult << ","
      << (glDst == ourDst && glResult == ourResult ? "yes" : "no") << "\n";
  }
  writeTextFile(path, w.str());
}

int runBlendCheck(const BlendCheckOptions& o) {
  const Profile profile = parseProfile(o.profile);
  std::vector<tools::BlendCase> cases;
  std::vector<size_t> lines;
  size_t bad = 0;
  if (!o.cases.empty()) {
    bad = readCases(o.cases, cases, lines);
  } else {
    tools::BlendCaseGeneratorOptions g;
    g.count = o.generate;
    g.seed = o.seed;
    g.nonFinite = o.nonFinite;
    cases = tools::generateBlendCases(g);
  }
  if (!o.writeCases.empty()) {
    std::ostringstream w;
    w << tools::blendCsvHeader(false) << "\n";
    for (const auto& c : cases) w << tools::blendCaseCsvLine(c) << "\n";
    writeTextFile(o.writeCases, w.str());
  }
  for (const auto& c : cases)
    if (c.format.id == FormatId::Minifloat)
      throw std::invalid_argument("format " + c.format.name() + " has no OpenGL equivalent");
  GlContext context;
  printDriver(context);
  std::cout << (o.cases.empty() ? "generated " + std::to_string(cases.size()) + " cases, seed " + std::to_string(o.seed) +
                                      (o.nonFinite ? ", with NaN and inf" : "")
                                : std::to_string(cases.size()) + " cases from " + o.cases)
            << "\n";
  const std::vector<tools::RecordedTexels> texels = runBlendCases(context, cases);
  const tools::BlendComparison s = tools::compareBlendCases(cases, texels, profile, lines, o.list, std::cout);
  if (!o.results.empty()) writeResults(o.results, cases, texels, profile);
  if (bad) std::cerr << "oitref glcheck blend: " << bad << " bad line(s) skipped\n";
  return bad ? 2 : (s.destinationMismatches || s.resultMismatches) ? 1 : 0;  // an error before a difference
}

struct SceneCheckCommand {
  SceneCheckOptions options;
  std::string size = "160x90", methods, memoryLimit, recordTrace, gpuReads;
  std::vector<std::string> sets;
};

int runSceneCheckCommand(SceneCheckCommand& c) {
  SceneCheckOptions& o = c.options;
  if (o.scenes.empty()) o.scenes = tools::sceneFiles("scenes");
  if (o.scenes.empty()) throw std::invalid_argument("no scenes given and none in ./scenes");
  if (!c.size.empty() && c.size != "scene") tools::parseSize(c.size, "--size", o.width, o.height);
  o.memoryLimit = tools::memoryLimitFrom(c.memoryLimit);
  o.methodOptions = tools::methodOptionsFrom(c.sets);
  o.methods.clear();
  for (size_t start = 0; start < c.methods.size();) {
    const size_t comma = c.methods.find(',', start);
    const std::string name = c.methods.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (!name.empty()) o.methods.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (!c.recordTrace.empty() && !c.gpuReads.empty())
    throw std::invalid_argument("--record-trace and --gpu-reads: one at a time (record here, replay there, compare here)");
  if (o.timeRuns > 0 && (!c.recordTrace.empty() || !c.gpuReads.empty()))
    throw std::invalid_argument("--time measures this driver: not with --record-trace or --gpu-reads");
  // Side by side means the same thread count: llvmpipe reads LP_NUM_THREADS when the context starts.
  if (o.threads > 0) {
    const char* lp = std::getenv("LP_NUM_THREADS");
    if (lp && std::string(lp) != std::to_string(o.threads))
      throw std::invalid_argument("--threads " + std::to_string(o.threads) + " but LP_NUM_THREADS=" + lp +
                                  ": give one thread count for both");
    setenv("LP_NUM_THREADS", std::to_string(o.threads).c_str(), 1);
  } else if (const char* lp = std::getenv("LP_NUM_THREADS")) {
    o.threads = std::atoi(lp);
    if (o.threads < 1) throw std::invalid_argument(std::string("LP_NUM_THREADS=") + lp + " is not a thread count");
  }
  GlContext context;
  printDriver(context);
  // Whole frames on another machine's GPU: record every GL call here, replay it there with
  // oitref-gpu-capture, then compare with the texels it read (gpucapture/gl_trace.h).
  std::ofstream trace;
  std::ifstream reads;
  if (!c.recordTrace.empty()) {
    trace.open(c.recordTrace, std::ios::binary);
    if (!trace) throw std::runtime_error("cannot write '" + c.recordTrace + "'");
    context.setFunctions(recordingFunctions(context.driver(), trace));
    std::cout << "recording every GL call into " << c.recordTrace << " (replay: oitref-gpu-capture frames)\n";
  }
  if (!c.gpuReads.empty()) {
    reads.open(c.gpuReads, std::ios::binary);
    if (!reads) throw std::runtime_error("cannot read '" + c.gpuReads + "'");
    context.setFunctions(substitutingFunctions(context.driver(), reads));
    std::cout << "GL texels: those recorded in " << c.gpuReads << " (replayed on another machine's GPU), not this driver's\n";
  }
  std::cout << "\n";
  const std::vector<SceneCheckRow> rows = runSceneCheck(context, o, std::cout);
  if (reads && reads.peek() != std::char_traits<char>::eof())
    throw std::runtime_error("'" + c.gpuReads + "' holds more reads than these frames make (recorded with other options?)");
  if (trace && !trace.flush()) throw std::runtime_error("writing '" + c.recordTrace + "' failed");
  size_t failed = 0;
  for (const SceneCheckRow& r : rows) failed += !r.pass;
  std::cout << rows.size() - failed << " of " << rows.size() << " scene × method pairs within tolerance\n";
  return failed ? 1 : 0;
}

}  // namespace
}  // namespace oitref::glcheck

namespace oitref::tools {

void addGlcheckCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand("glcheck", "Check oitref against a real OpenGL driver (headless EGL), bit for bit");
  cmd->require_subcommand(1);

  auto b = std::make_shared<glcheck::BlendCheckOptions>();
  CLI::App* blend = cmd->add_subcommand("blend", "Blend cases on the GL driver and in oitref; exit 1 on any bit difference");
  blend->add_option("--cases", b->cases, "CSV of cases as `oitref blend --cases` reads them (default: generate)");
  blend->add_option("--generate", b->generate, "Number of random cases to generate (at most 10 million: ~1 GiB)")
      ->capture_default_str()
      ->check(CLI::Range(size_t(1), size_t(10'000'000)));
  blend->add_option("--seed", b->seed, "Seed of the generated cases")->capture_default_str();
  blend->add_flag("--nonfinite", b->nonFinite, "Generate NaN and infinities too");
  blend->add_option("--write-cases", b->writeCases, "Also write the cases as CSV (for `oitref blend --cases`)");
  blend->add_option("--results", b->results, "Write every case with GL's and oitref's bits as CSV");
  tools::addProfileOption(blend, b->profile, "oitref profile to compare with");
  blend->add_option("--list", b->list, "How many mismatches to list")->capture_default_str();
  blend->callback([b, &exitCode] { exitCode = runReportingErrors("glcheck blend", [&] { return glcheck::runBlendCheck(*b); }); });

  auto s = std::make_shared<glcheck::SceneCheckCommand>();
  std::string methodList;
  for (const std::string& m : glcheck::glMethodNames()) methodList += (methodList.empty() ? "" : ",") + m;
  CLI::App* scene = cmd->add_subcommand(
      "scene", "Scenes rendered by each method's GL version and by oitref; exit 1 when a method is out of tolerance");
  scene->add_option("scenes", s->options.scenes, "Scene files (default: every scenes/*.json)");
  scene->add_option("--methods", s->methods, "Comma-separated methods (default: " + methodList + ")");
  tools::addMethodSetOption(scene, s->sets);
  scene->add_option("--size", s->size, "Resolution WxH, or 'scene' for the scene's own")->capture_default_str();
  tools::addProfileOption(scene, s->options.profile, "oitref profile to compare with");
  scene->add_option("--tolerance", s->options.tolerance,
                    "Per-pixel error allowed on the RGBA8 image (default 0 for profiles with raster=llvmpipe, where "
                    "every attachment must be bit-equal too; else 1.5/255: one step passes, two fail)")
      ->check(CLI::Range(0.0, 1.0));
  scene->add_option("--min-share", s->options.minShare,
                    "Share of pixels within tolerance a method needs (default 1 with raster=llvmpipe, else 0.99)")
      ->check(CLI::Range(0.0, 1.0));
  tools::addMemoryLimitOption(scene, s->memoryLimit);
  scene->add_option("--time", s->options.timeRuns,
                    "Also time each method N times, oitref and GL alternated, with min/median wall and CPU ms and the ratio")
      ->check(CLI::Range(1, 1000));
  scene->add_option("--threads", s->options.threads,
                    "oitref's threads, and llvmpipe's through LP_NUM_THREADS (default: LP_NUM_THREADS, else every hardware thread)")
      ->check(CLI::Range(1, 1024));
  scene->add_option("--heatmaps", s->options.heatmaps, "Write GL and oitref images and error heatmaps into this folder");
  scene->add_option("--record-trace", s->recordTrace,
                    "Also record every GL call into this file, for oitref-gpu-capture frames on a GPU machine");
  scene->add_option("--gpu-reads", s->gpuReads,
                    "Compare with the texels oitref-gpu-capture frames read on a GPU (same scenes and options as the recording)");
  scene->callback([s, &exitCode] {
    exitCode = runReportingErrors("glcheck scene", [&] { return glcheck::runSceneCheckCommand(*s); });
  });

}

}  // namespace oitref::tools
