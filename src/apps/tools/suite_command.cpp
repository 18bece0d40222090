// `oitref suite` (every scene × method, with tables) and `oitref reference` (the golden set).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "tools/commands.h"
#include "tools/number_parse.h"
#include "tools/suite.h"
#include "tools/suite_jobs.h"

namespace oitref::tools {
namespace {

struct SuiteOptions {
  std::vector<std::string> scenes;
  std::string out, size, profile = "exact", dir = "reference", scenesDir = "scenes", memoryLimit, plan;
  int threads = 0;
  bool write = false;
};

CLI::Option* addPlanOption(CLI::App* cmd, std::string& plan, const char* what) {
  return nonEmptyPath(cmd->add_option("--plan", plan,
                                      std::string("Render nothing: write ") + what +
                                          " as jobs (one per scene) into this plan folder, for `oitref job` (e.g. on Slurm: "
                                          "scripts/slurm/submit.sh) and `oitref collect`"));
}

}  // namespace

void addSuiteCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<SuiteOptions>();
  CLI::App* suite = app.add_subcommand("suite", "Render scenes with every method; print time, memory and error vs the A-buffer");
  suite->add_option("scenes", o->scenes, "Scene files (default: every scenes/*.json)");
  nonEmptyPath(suite->add_option("--out", o->out, "Write every image into this folder"));
  addSizeOption(suite, o->size);
  addThreadsOption(suite, o->threads);
  addProfileOption(suite, o->profile);
  addMemoryLimitOption(suite, o->memoryLimit);
  addPlanOption(suite, o->plan, "the suite");
  suite->callback([o, &exitCode] {
    exitCode = runReportingErrors("suite", [&] {
      SuiteRequest r;
      r.scenes = o->scenes.empty() ? sceneFiles("scenes") : o->scenes;
      if (!o->size.empty()) parseSize(o->size, "--size", r.width, r.height);
      r.out = o->out, r.profileText = o->profile, r.memoryLimitText = o->memoryLimit;
      const Profile profile = parseProfile(o->profile);
      const uint64_t limit = memoryLimitFrom(o->memoryLimit);
      if (!o->plan.empty()) {
        const Plan plan = planSuite(r, o->plan);
        std::fputs(plannedMessage("suite", plan, "the tables" + (r.out.empty() ? std::string() : " and the images into " + r.out)).c_str(), stdout);
        return 0;
      }
      Renderer renderer(RendererOptions{.threads = o->threads});
      std::printf("oitref suite: %zu scenes, threads %d, profile %s\n\n", r.scenes.size(), renderer.threads(), profile.name.c_str());
      for (const std::string& path : r.scenes) {
        std::fputs(formatSuiteTable(runSuiteScene(path, renderer, profile, r.width, r.height, r.out, limit)).c_str(), stdout);
        std::fputs("\n", stdout);
        std::fflush(stdout);
      }
      if (!r.out.empty()) std::printf("images in %s/<scene>/<method>.png|.exr\n", r.out.c_str());
      return 0;
    });
  });

  CLI::App* ref = app.add_subcommand("reference", "Check (or, with --write, regenerate) the golden reference images");
  ref->add_option("--dir", o->dir, "Reference folder")->capture_default_str();
  ref->add_option("--scenes", o->scenesDir, "Scene folder")->capture_default_str();
  addThreadsOption(ref, o->threads);
  ref->add_flag("--write", o->write, "Regenerate the images and the manifest (only on purpose)");
  std::shared_ptr<std::string> refProfile = std::make_shared<std::string>("exact");
  ref->add_option("--profile", *refProfile,
                  "Golden set of this profile: exact (images and manifest.txt) or llvmpipe (manifest_llvmpipe.txt, hashes only)")
      ->check(CLI::IsMember({"exact", "llvmpipe"}))
      ->capture_default_str();
  addPlanOption(ref, o->plan, "the check (or with --write, the regeneration)");
  ref->callback([o, refProfile, &exitCode] {
    exitCode = runReportingErrors("reference", [&] {
      const std::string& profile = *refProfile;
      if (!o->plan.empty() && profile != "exact") throw std::invalid_argument("--plan checks the exact profile's golden set only");
      if (!o->plan.empty()) {
        const Plan plan = planReference(o->scenesDir, o->dir, o->write, o->plan);
        std::fputs(plannedMessage("reference", plan, o->write ? "the images and manifest into " + o->dir : "the check against " + o->dir).c_str(), stdout);
        return 0;
      }
      Renderer renderer(RendererOptions{.threads = o->threads});
      if (o->write) std::filesystem::create_directories(o->dir);
      if (!o->write) readManifest(referenceManifest(o->dir, profile));  // an unreadable manifest fails before rendering
      return reportReferences(renderReferences(o->scenesDir, renderer, o->dir, o->write, profile), o->dir, o->write, profile);
    });
  });
}

}  // namespace oitref::tools
