// `oitref study SCENE... --out DIR`: the speed–accuracy report.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "tools/commands.h"
#include "oitref/oit/image_io.h"
#include "tools/study.h"
#include "tools/study_report.h"
#include "tools/suite.h"

namespace oitref::tools {
namespace {

struct StudyCommandOptions {
  std::vector<std::string> scenes, methods;
  std::string out = "out/study", size, profile = "exact", memoryLimit;
  int threads = 0, runs = 5;
  double heatmapScale = 0.25;
  bool quiet = false;
};

// "[ 12/210] 00:07 ballpark: wboit weight=mb7": a line per item, or one line rewritten in place
// when stderr is a terminal.
StudyProgress progressPrinter(bool quiet) {
  if (quiet) return [](const std::string&, int, int) {};
  const bool terminal = isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  return [terminal, start](const std::string& what, int i, int n) {
    const int s = int(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::fprintf(stderr, "%s[%*d/%d] %02d:%02d %s%s", terminal ? "\r\033[K" : "", int(std::to_string(n).size()), i, n,
                 s / 60, s % 60, what.c_str(), terminal ? "" : "\n");
    std::fflush(stderr);
  };
}

int runStudyCommand(const StudyCommandOptions& c) {
  StudyOptions o;
  o.scenes = c.scenes.empty() ? sceneFiles("scenes") : c.scenes;
  for (const std::string& path : o.scenes)
    if (!std::filesystem::is_regular_file(path)) throw std::invalid_argument(path + ": no such scene file");
  o.outDir = c.out;
  if (!c.size.empty()) parseSize(c.size, "--size", o.width, o.height);
  if (c.runs < 1 || c.runs > 1000) throw std::invalid_argument("--runs must be in 1..1000");
  if (!(c.heatmapScale > 0)) throw std::invalid_argument("--heatmap-scale must be above 0");
  o.runs = c.runs, o.heatmapScale = c.heatmapScale, o.methods = c.methods;
  o.profile = parseProfile(c.profile);
  o.memoryLimit = memoryLimitFrom(c.memoryLimit);
  Renderer renderer(RendererOptions{.threads = c.threads});
  const StudyResult result = runStudy(o, renderer, progressPrinter(c.quiet));
  if (!c.quiet && isatty(STDERR_FILENO)) std::fputs("\n", stderr);
  const std::filesystem::path dir(c.out);
  writeTextFile((dir / "results.json").string(), studyJson(result));
  writeTextFile((dir / "results.csv").string(), studyCsv(result));
  writeTextFile((dir / "index.html").string(), studyHtml(result));
  std::printf("oitref study: %zu scenes × %zu configurations, %d threads, %.1f s\nreport: %s\n", result.scenes.size(),
              result.scenes.empty() ? size_t(0) : result.scenes[0].rows.size(), result.threads, result.totalSeconds,
              std::filesystem::absolute(dir / "index.html").lexically_normal().c_str());
  return 0;
}

}  // namespace

void addStudyCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<StudyCommandOptions>();
  CLI::App* cmd = app.add_subcommand("study", "Time every method and variant on scenes, measure their error, write an HTML report");
  cmd->add_option("scenes", o->scenes, "Scene files (default: every scenes/*.json)");
  nonEmptyPath(cmd->add_option("--out", o->out, "Report folder"))->capture_default_str();
  cmd->add_option("--methods", o->methods, "Only these methods, comma- or space-separated (the A-buffer and the ray cast always run)")->delimiter(',');
  addSizeOption(cmd, o->size);
  cmd->add_option("--runs", o->runs, "Timed runs per configuration, after one warm-up (which counts as the first run where it took 100 ms or more)")->capture_default_str();
  addThreadsOption(cmd, o->threads);
  addProfileOption(cmd, o->profile);
  cmd->add_option("--heatmap-scale", o->heatmapScale, "Error drawn white in the heatmaps")->capture_default_str();
  addQuietFlag(cmd, o->quiet);
  addMemoryLimitOption(cmd, o->memoryLimit);
  cmd->callback([o, &exitCode] { exitCode = runReportingErrors("study", [&] { return runStudyCommand(*o); }); });
}

}  // namespace oitref::tools
