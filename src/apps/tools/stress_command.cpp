// `oitref stress --out DIR`: the stability atlas.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "tools/commands.h"
#include "oitref/oit/image_io.h"
#include "tools/stress.h"
#include "tools/stress_report.h"

namespace oitref::tools {
namespace {

struct StressCommandOptions {
  std::vector<std::string> conditions, methods;
  std::string out = "out/stress";
  int threads = 0, size = 4, maxLayers = 4096;
  bool quiet = false;
};

int runStressCommand(const StressCommandOptions& c) {
  StressOptions o;
  o.conditions = c.conditions, o.methods = c.methods, o.size = c.size;
  o.layers.clear();
  for (int n : kStressLayers)
    if (n <= c.maxLayers) o.layers.push_back(n);
  if (o.layers.empty()) throw std::invalid_argument("--max-layers must be at least 1");
  Renderer renderer(RendererOptions{.threads = c.threads});
  const bool terminal = isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::vector<StressRow> rows = runStress(o, renderer, [&](const std::string& what, int i, int n) {
    if (c.quiet) return;
    const int s = int(seconds());
    std::fprintf(stderr, "%s[%d/%d] %02d:%02d %s%s", terminal ? "\r\033[K" : "", i, n, s / 60, s % 60, what.c_str(),
                 terminal ? "" : "\n");
    std::fflush(stderr);
  });
  if (!c.quiet && terminal) std::fputs("\n", stderr);
  const std::filesystem::path dir(c.out);
  std::filesystem::create_directories(dir);
  writeTextFile((dir / "atlas.json").string(), stressJson(rows, o));
  writeTextFile((dir / "atlas.csv").string(), stressCsv(rows));
  writeTextFile((dir / "atlas.html").string(), stressHtml(rows, o, seconds()));
  size_t failures = 0;
  for (const StressRow& r : rows) failures += stressFindings(r).size();
  std::printf("oitref stress: %zu rows × %zu cells, %zu failure kinds found, %.1f s\natlas: %s\n", rows.size(),
              o.layers.size() * o.alphas.size(), failures, seconds(),
              std::filesystem::absolute(dir / "atlas.html").lexically_normal().c_str());
  return 0;
}

}  // namespace

void addStressCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<StressCommandOptions>();
  CLI::App* cmd = app.add_subcommand("stress", "The stability atlas: every method and format at the extremes");
  nonEmptyPath(cmd->add_option("--out", o->out, "Atlas folder"))->capture_default_str();
  cmd->add_option("--conditions", o->conditions, "Only these conditions (base, colocated, wide, distant, scaled_x100, "
                                                 "scaled_x0.01, hdr, bright)");
  cmd->add_option("--methods", o->methods, "Only these methods (comma- or space-separated)")->delimiter(',');
  cmd->add_option("--max-layers", o->maxLayers, "Largest layer count of the sweep (default 4096)")->capture_default_str();
  cmd->add_option("--size", o->size, "Pixels per side of each cell's image")->check(CLI::Range(1, 64))->capture_default_str();
  addThreadsOption(cmd, o->threads);
  addQuietFlag(cmd, o->quiet);
  cmd->callback([o, &exitCode] { exitCode = runReportingErrors("stress", [&] { return runStressCommand(*o); }); });
}

}  // namespace oitref::tools
