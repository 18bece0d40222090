// `oitref study SCENE... --out DIR`: the speed–accuracy report.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "tools/commands.h"
#include "oitref/oit/image_io.h"
#include "tools/study.h"
#include "tools/study_jobs.h"
#include "tools/study_report.h"
#include "tools/suite.h"

namespace oitref::tools {
namespace {

struct StudyCommandOptions {
  std::vector<std::string> scenes, methods;
  std::string out = "out/study", size, profile = "exact", memoryLimit, plan;
  int threads = 0, runs = 5, perJob = 0;
  double heatmapScale = 0.25;
  bool quiet = false;
};

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
  if (!c.plan.empty()) {
    const Plan plan = planStudy({o, c.profile, c.memoryLimit, c.perJob}, c.plan);
    std::fputs(plannedMessage("study", plan, "the report into " + plan.options.at("out").get<std::string>()).c_str(), stdout);
    return 0;
  }
  Renderer renderer(RendererOptions{.threads = c.threads});
  const StudyResult result = runStudy(o, renderer, studyProgressPrinter(c.quiet));
  if (!c.quiet && isatty(STDERR_FILENO)) std::fputs("\n", stderr);
  const std::filesystem::path dir(c.out);
  writeStudyReport(result, c.out);
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
  CLI::Option* plan = nonEmptyPath(cmd->add_option("--plan", o->plan,
                               "Render nothing: write the study as jobs into this plan folder, for `oitref job` (e.g. on a "
                               "Slurm cluster: scripts/slurm/submit.sh) and `oitref collect`"));
  cmd->add_option("--configurations-per-job", o->perJob,
                  "With --plan: configurations of one scene per job (default: about 2^28 pixel-frames of work a job)")
      ->check(CLI::Range(1, 100000))->needs(plan);
  cmd->callback([o, &exitCode] { exitCode = runReportingErrors("study", [&] { return runStudyCommand(*o); }); });
}

}  // namespace oitref::tools
