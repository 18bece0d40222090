// Every built-in scene with every method: the README's main job (a table per scene of time,
// memory and error against the A-buffer) and the golden reference images.
#pragma once

#include <string>
#include <vector>

#include "oitref/oit/frame.h"
#include "oitref/oit/method.h"

namespace oitref::tools {

struct SuiteRow {
  std::string method;
  double ms = 0;
  int bytesPerPixel = 0;
  double rmse = 0, maxError = 0;  // RGB of the float result against the A-buffer's
  std::string note;               // the frame's figures worth a glance (FrameStats: peeling passes, …)
};

struct SuiteScene {
  std::string name;
  int width = 0, height = 0;
  uint64_t fragments = 0;
  std::vector<SuiteRow> rows;
};

// The *.json files of a folder, sorted by name.
std::vector<std::string> sceneFiles(const std::string& folder);
// Scene name from its path: "scenes/ballpark.json" -> "ballpark".
std::string sceneName(const std::string& path);

// Renders `scenePath` with every method at its default options (the A-buffer first, as the
// reference for the errors). width/height 0: the scene's own resolution. Writes
// outDir/<scene>/<method>.png and .exr when outDir is not empty.
SuiteScene runSuiteScene(const std::string& scenePath, Renderer& renderer, const Profile& profile, int width, int height,
                         const std::string& outDir, uint64_t memoryLimit);
std::string formatSuiteTable(const SuiteScene& scene);

// The golden set: every scene × method at kReferenceWidth × kReferenceHeight.
inline constexpr int kReferenceWidth = 96, kReferenceHeight = 72;
struct ReferenceEntry {
  std::string scene, method, hash;
};
// Renders the golden set; writes <dir>/<scene>_<method>.png and <dir>/manifest.txt when `write`.
std::vector<ReferenceEntry> renderReferences(const std::string& scenesDir, Renderer& renderer, const std::string& dir,
                                             bool write, const std::string& profile = "exact");
std::vector<ReferenceEntry> readManifest(const std::string& path);
// One scene's part of the golden set (its images into `dir` when `write`).
std::vector<ReferenceEntry> renderReferenceScene(const std::string& scenePath, Renderer& renderer, const std::string& dir,
                                                 bool write, const std::string& profile = "exact");
void writeReferenceManifest(const std::string& dir, const std::vector<ReferenceEntry>& entries,
                            const std::string& profile = "exact");
// The manifest of a profile's golden hashes: manifest.txt for exact (with the images), else
// manifest_<profile>.txt (hashes only: the llvmpipe profile's frames, bit-equal to Mesa's).
std::string referenceManifest(const std::string& dir, const std::string& profile);
// What `oitref reference` prints about the rendered entries: with `write`, that they were
// written; else each that differs from, is missing in or is new to dir/manifest.txt. Returns the
// exit status (1: any difference).
int reportReferences(const std::vector<ReferenceEntry>& entries, const std::string& dir, bool write,
                     const std::string& profile = "exact");

}  // namespace oitref::tools
