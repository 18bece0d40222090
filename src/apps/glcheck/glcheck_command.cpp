// `oitref glcheck`: checks oitref against a real OpenGL driver (headless, through EGL).
//   glcheck blend  the blend cases of `oitref blend --cases`, or generated ones, bit for bit
//   glcheck scene  scenes rendered by the GL version of each method, against `oitref render`
//   glcheck raster random triangles one at a time: coverage, depth and interpolation per raster rule
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "glcheck/blend_check.h"
#include "glcheck/gl_context.h"
#include "glcheck/gl_methods.h"
#include "glcheck/raster_check.h"
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

// A GPU on another machine: every GL call recorded here (--record-trace), replayed there with
// oitref-gpu-capture frames, then the same calls run again here with the texels it read in place
// of this driver's (--gpu-reads; gpucapture/gl_trace.h). Neither: the context is left as it is.
class TraceLink {
 public:
  TraceLink(GlContext& context, const std::string& recordTrace, const std::string& gpuReads)
      : recordTrace_(recordTrace), gpuReads_(gpuReads) {
    if (!recordTrace.empty() && !gpuReads.empty())
      throw std::invalid_argument("--record-trace and --gpu-reads: one at a time (record here, replay there, compare here)");
    if (!recordTrace.empty()) {
      trace_.open(recordTrace, std::ios::binary);
      if (!trace_) throw std::runtime_error("cannot write '" + recordTrace + "'");
      context.setFunctions(recordingFunctions(context.driver(), trace_));
      std::cout << "recording every GL call into " << recordTrace << " (replay: oitref-gpu-capture frames)\n";
    }
    if (!gpuReads.empty()) {
      reads_.open(gpuReads, std::ios::binary);
      if (!reads_) throw std::runtime_error("cannot read '" + gpuReads + "'");
      context.setFunctions(substitutingFunctions(context.driver(), reads_));
      std::cout << "GL texels: those recorded in " << gpuReads << " (replayed on another machine's GPU), not this driver's\n";
    }
  }
  // After the last GL call: every recorded read used, the trace written.
  void finish() {
    if (reads_.is_open() && reads_.peek() != std::char_traits<char>::eof())
      throw std::runtime_error("'" + gpuReads_ + "' holds more reads than these frames make (recorded with other options?)");
    if (trace_.is_open() && !trace_.flush()) throw std::runtime_error("writing '" + recordTrace_ + "' failed");
  }

 private:
  std::string recordTrace_, gpuReads_;
  std::ofstream trace_;
  std::ifstream reads_;
};

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
  TraceLink link(context, c.recordTrace, c.gpuReads);
  std::cout << "\n";
  const std::vector<SceneCheckRow> rows = runSceneCheck(context, o, std::cout);
  link.finish();
  size_t failed = 0;
  for (const SceneCheckRow& r : rows) failed += !r.pass;
  std::cout << rows.size() - failed << " of " << rows.size() << " scene × method pairs within tolerance\n";
  return failed ? 1 : 0;
}

struct RasterCheckCommand {
  RasterCheckOptions options;
  std::string profiles = "exact;llvmpipe", recordTrace, gpuReads;
};

int runRasterCheckCommand(RasterCheckCommand& c) {
  RasterCheckOptions& o = c.options;
  o.profiles.clear();
  for (size_t start = 0; start <= c.profiles.size();) {  // profiles are separated by ';' (a profile holds commas)
    const size_t end = std::min(c.profiles.find(';', start), c.profiles.size());
    if (end > start) o.profiles.push_back(c.profiles.substr(start, end - start));
    start = end + 1;
  }
  if (o.profiles.empty()) throw std::invalid_argument("--profiles names no profile");
  if (o.require == "none") o.require.clear();
  GlContext context;
  printDriver(context);
  TraceLink link(context, c.recordTrace, c.gpuReads);
  std::cout << "\n";
  const RasterCheckResult r = runRasterCheck(context, o, std::cout);
  link.finish();
  if (!o.require.empty())
    std::cout << "\n"
              << (o.requireCoverageOnly ? (r.pass ? "every pixel covered alike" : "coverage differs")
                                        : (r.pass ? "every pixel equal" : "pixels differ"))
              << " under " << o.require << "\n";
  return r.pass ? 0 : 1;
}

}  // namespace
}  // namespace oitref::glcheck

namespace oitref::tools {
namespace {

// glcheck::TraceLink's two files.
void addTraceOptions(CLI::App* cmd, std::string& recordTrace, std::string& gpuReads) {
  cmd->add_option("--record-trace", recordTrace,
                  "Also record every GL call into this file, for oitref-gpu-capture frames on a GPU machine");
  cmd->add_option("--gpu-reads", gpuReads,
                  "Compare with the texels oitref-gpu-capture frames read on a GPU (same scenes and options as the recording)");
}

}  // namespace

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
  addTraceOptions(scene, s->recordTrace, s->gpuReads);
  scene->callback([s, &exitCode] {
    exitCode = runReportingErrors("glcheck scene", [&] { return glcheck::runSceneCheckCommand(*s); });
  });

  auto r = std::make_shared<glcheck::RasterCheckCommand>();
  CLI::App* raster = cmd->add_subcommand(
      "raster", "Random triangles, each alone, on the GL driver and in oitref: coverage, D32F depth and interpolation "
                "per raster rule; exit 1 when the required rule differs anywhere");
  raster->add_option("--triangles", r->options.triangles, "How many triangles")->capture_default_str()->check(CLI::Range(1, 100000));
  raster->add_option("--seed", r->options.seed, "Seed of the triangles")->capture_default_str();
  raster->add_option("--size", r->options.size, "Framebuffer side in pixels, a power of two")->capture_default_str();
  raster->add_option("--profiles", r->profiles, "oitref profiles to compare, separated by ';' (those with fill=state once with each fill convention)")
      ->capture_default_str();
  raster->add_option("--require", r->options.require, "The profile that must match in every pixel ('none': report only)")
      ->capture_default_str();
  raster->add_flag("--require-coverage", r->options.requireCoverageOnly,
                   "--require asks for the same covered pixels only; depth and interpolation are reported");
  addTraceOptions(raster, r->recordTrace, r->gpuReads);
  raster->callback([r, &exitCode] {
    exitCode = runReportingErrors("glcheck raster", [&] { return glcheck::runRasterCheckCommand(*r); });
  });

}

}  // namespace oitref::tools
