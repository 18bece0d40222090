// `oitref stress --out DIR`: the stability atlas.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "tools/commands.h"
#include "oitref/oit/image_io.h"
#include "tools/stress.h"
#include "tools/stress_jobs.h"
#include "tools/study.h"
#include "tools/stress_report.h"

namespace oitref::tools {
namespace {

struct StressCommandOptions {
  std::vector<std::string> conditions, methods;
  std::string out = "out/stress";
  std::string plan;
  int threads = 0, size = 4, maxLayers = 4096, rowsPerJob = 0;
  bool quiet = false;
};

int runStressCommand(const StressCommandOptions& c) {
  StressOptions o;
  o.conditions = c.conditions, o.methods = c.methods, o.size = c.size;
  o.layers.clear();
  for (int n : kStressLayers)
    if (n <= c.maxLayers) o.layers.push_back(n);
  if (o.layers.empty()) throw std::invalid_argument("--max-layers must be at least 1");
  if (!c.plan.empty()) {
    const Plan plan = planStress(o, c.out, c.rowsPerJob, c.plan);
    std::fputs(plannedMessage("stress", plan, "the atlas into " + plan.options.at("out").get<std::string>()).c_str(), stdout);
    return 0;
  }
  Renderer renderer(RendererOptions{.threads = c.threads});
  const bool terminal = isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::vector<StressRow> rows = runStress(o, renderer, studyProgressPrinter(c.quiet));
  if (!c.quiet && terminal) std::fputs("\n", stderr);
  writeStressAtlas(rows, o, seconds(), "", c.out);
  return 0;
}

}  // namespace

void addStressCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<StressCommandOptions>();
  CLI::App* cmd = app.add_subcommand("stress", "The stability atlas: every method and format at the extremes");
  nonEmptyPath(cmd->add_option("--out", o->out, "Atlas folder"))->capture_default_str();
  cmd->add_option("--conditions", o->conditions, "Only these conditions (base, colocated, wide, distant, scaled_x100, "
                                                 "scaled_x0.01, hdr, bright; comma- or space-separated)")->delimiter(',');
  cmd->add_option("--methods", o->methods, "Only these methods (comma- or space-separated)")->delimiter(',');
  cmd->add_option("--max-layers", o->maxLayers, "Largest layer count of the sweep (default 4096)")->capture_default_str();
  cmd->add_option("--size", o->size, "Pixels per side of each cell's image")->check(CLI::Range(1, 64))->capture_default_str();
  addThreadsOption(cmd, o->threads);
  addQuietFlag(cmd, o->quiet);
  CLI::Option* plan = nonEmptyPath(cmd->add_option("--plan", o->plan,
      "Render nothing: write the atlas as jobs into this plan folder, for `oitref job` (e.g. on Slurm: "
      "scripts/slurm/submit.sh) and `oitref collect`"));
  cmd->add_option("--rows-per-job", o->rowsPerJob, "With --plan: atlas rows (a condition × a configuration) per job (default: about two minutes of a core, 3840 / size² rows)")
      ->check(CLI::Range(1, 100000))->needs(plan);
  cmd->callback([o, &exitCode] { exitCode = runReportingErrors("stress", [&] { return runStressCommand(*o); }); });
}

}  // namespace oitref::tools
