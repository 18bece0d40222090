// `oitref suite` (every scene × method, with tables) and `oitref reference` (the golden set).
#include <map>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "tools/commands.h"
#include "tools/number_parse.h"
#include "tools/suite.h"

namespace oitref::tools {
namespace {

struct SuiteOptions {
  std::vector<std::string> scenes;
  std::string out, size, profile = "exact", dir = "reference", scenesDir = "scenes", memoryLimit;
  int threads = 0;
  bool write = false;
};

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
  suite->callback([o, &exitCode] {
    exitCode = runReportingErrors("suite", [&] {
      std::vector<std::string> scenes = o->scenes.empty() ? sceneFiles("scenes") : o->scenes;
      int w = 0, h = 0;
      if (!o->size.empty()) parseSize(o->size, "--size", w, h);
      const uint64_t limit = memoryLimitFrom(o->memoryLimit);
      Renderer renderer(RendererOptions{.threads = o->threads});
      const Profile profile = parseProfile(o->profile);
      std::printf("oitref suite: %zu scenes, threads %d, profile %s\n\n", scenes.size(), renderer.threads(), profile.name.c_str());
      for (const std::string& path : scenes) {
        std::fputs(formatSuiteTable(runSuiteScene(path, renderer, profile, w, h, o->out, limit)).c_str(), stdout);
        std::fputs("\n", stdout);
        std::fflush(stdout);
      }
      if (!o->out.empty()) std::printf("images in %s/<scene>/<method>.png|.exr\n", o->out.c_str());
      return 0;
    });
  });

  CLI::App* ref = app.add_subcommand("reference", "Check (or, with --write, regenerate) the golden reference images");
  ref->add_option("--dir", o->dir, "Reference folder")->capture_default_str();
  ref->add_option("--scenes", o->scenesDir, "Scene folder")->capture_default_str();
  addThreadsOption(ref, o->threads);
  ref->add_flag("--write", o->write, "Regenerate the images and the manifest (only on purpose)");
  ref->callback([o, &exitCode] {
    exitCode = runReportingErrors("reference", [&] {
      Renderer renderer(RendererOptions{.threads = o->threads});
      if (o->write) std::filesystem::create_directories(o->dir);
      const auto manifest = o->write ? std::vector<ReferenceEntry>{} : readManifest(o->dir + "/manifest.txt");
      const auto entries = renderReferences(o->scenesDir, renderer, o->dir, o->write);
      // Matched by (scene, method), so a new method or scene shows up as new images while the
      // existing ones are still compared hash for hash.
      int bad = 0, fresh = 0, same = 0;
      std::map<std::pair<std::string, std::string>, std::string> expected;
      for (const auto& m : manifest) expected[{m.scene, m.method}] = m.hash;
      for (const auto& e : entries) {
        const auto it = expected.find({e.scene, e.method});
        if (o->write) continue;
        if (it == expected.end()) {
          std::printf("new (not in the manifest): %s %s\n", e.scene.c_str(), e.method.c_str()), ++fresh;
          continue;
        }
        if (it->second != e.hash) std::printf("differs: %s %s\n", e.scene.c_str(), e.method.c_str()), ++bad;
        else ++same;
        expected.erase(it);
      }
      for (const auto& [key, hash] : expected)
        if (!o->write) std::printf("missing (in the manifest, not rendered): %s %s\n", key.first.c_str(), key.second.c_str()), ++bad;
      if (!o->write && (bad || fresh))
        std::printf("%d differ or are missing, %d are new, %d identical\n", bad, fresh, same);
      bad += fresh;
      std::printf("%s %zu reference images\n", o->write ? "wrote" : (bad ? "FAILED:" : "identical:"), entries.size());
      return bad ? 1 : 0;
    });
  });
}

}  // namespace oitref::tools
