#include "tools/suite.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "oitref/oit/metrics.h"
#include "oitref/oit/frame.h"
#include "oitref/oit/image_io.h"

namespace oitref::tools {
namespace fs = std::filesystem;

std::vector<std::string> sceneFiles(const std::string& folder) {
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().extension() == ".json") out.push_back(entry.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string sceneName(const std::string& path) { return fs::path(path).stem().string(); }

SuiteScene runSuiteScene(const std::string& scenePath, Renderer& renderer, const Profile& profile, int width, int height,
                         const std::string& outDir, uint64_t memoryLimit) {
  Scene scene = loadScene(scenePath, memoryLimit);
  if (width > 0) scene.width = width, scene.height = height;
  const SceneFrames frames(std::move(scene), renderer, profile, memoryLimit);
  SuiteScene result;
  result.name = sceneName(scenePath);
  result.width = frames.scene().width, result.height = frames.scene().height;
  std::vector<MethodInfo> methods = allMethods();
  std::stable_partition(methods.begin(), methods.end(), [](const MethodInfo& m) { return m.name == "abuffer"; });
  Image truth;
  for (const MethodInfo& info : methods) {
    std::unique_ptr<Method> method = makeMethod(info.name);
    const FrameResult frame = frames.render(*method);
    if (info.name == "abuffer") {
      truth = frame.finalFloat;
      result.fragments = frame.stats.fragments.value_or(0);
    }
    const ImageDifference d = compareImages(frame.finalFloat, truth, 0.0);
    SuiteRow row{info.name, frame.frameMs(), method->bytesPerPixel(), d.rmse, d.maxAbs, ""};
    if (d.nonFinitePixels) row.note = std::to_string(d.nonFinitePixels) + " non-finite pixels (not in RMSE)";
    for (const auto& [k, v] : frame.stats.lines())
      if (k == "peeling passes" || k == "passes that peeled a layer" || k == "all layers peeled" || k == "depth complexity max")
        row.note += (row.note.empty() ? "" : ", ") + k + ": " + v;
    result.rows.push_back(row);
    if (!outDir.empty()) {
      const fs::path dir = fs::path(outDir) / result.name;
      fs::create_directories(dir);
      writeImage((dir / (info.name + ".png")).string(), frame.final8);
      writeImage((dir / (info.name + ".exr")).string(), frame.finalFloat);
    }
  }
  return result;
}

std::string formatSuiteTable(const SuiteScene& s) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line, "%s  (%dx%d, %llu transparent fragments)\n", s.name.c_str(), s.width, s.height,
                (unsigned long long)s.fragments);
  out << line;
  std::snprintf(line, sizeof line, "  %-8s %10s %8s %12s %12s  %s\n", "method", "ms", "B/pixel", "RMSE", "max error", "notes");
  out << line;
  for (const SuiteRow& r : s.rows) {
    std::snprintf(line, sizeof line, "  %-8s %10.2f %8d %12.3e %12.3e  %s\n", r.method.c_str(), r.ms, r.bytesPerPixel, r.rmse,
                  r.maxError, r.note.c_str());
    out << line;
  }
  return out.str();
}

std::vector<ReferenceEntry> renderReferenceScene(const std::string& path, Renderer& renderer, const std::string& dir, bool write,
                                                 const std::string& profile) {
  Scene scene = loadScene(path);
  scene.width = kReferenceWidth, scene.height = kReferenceHeight;
  const SceneFrames frames(std::move(scene), renderer, parseProfile(profile));
  std::vector<ReferenceEntry> entries;
  for (const MethodInfo& info : allMethods()) {
    const FrameResult frame = frames.render(*makeMethod(info.name));
    entries.push_back({sceneName(path), info.name, frameHash(frame)});
    if (write && profile == "exact") writeImage((fs::path(dir) / (sceneName(path) + "_" + info.name + ".png")).string(), frame.final8);
  }
  return entries;
}

std::string referenceManifest(const std::string& dir, const std::string& profile) {
  return (fs::path(dir) / (profile == "exact" ? std::string("manifest.txt") : "manifest_" + profile + ".txt")).string();
}

void writeReferenceManifest(const std::string& dir, const std::vector<ReferenceEntry>& entries, const std::string& profile) {
  std::ostringstream manifest;
  manifest << "# scene method sha256(final RGBA8 bits, then RGBA32F bits), " << kReferenceWidth << "x" << kReferenceHeight
           << ", profile " << profile << ". Regenerate with `oitref reference --write"
           << (profile == "exact" ? "" : " --profile " + profile) << "` only on purpose.\n";
  for (const ReferenceEntry& e : entries) manifest << e.scene << " " << e.method << " " << e.hash << "\n";
  writeTextFile(referenceManifest(dir, profile), manifest.str());
}

std::vector<ReferenceEntry> renderReferences(const std::string& scenesDir, Renderer& renderer, const std::string& dir,
                                             bool write, const std::string& profile) {
  std::vector<ReferenceEntry> entries;
  for (const std::string& path : sceneFiles(scenesDir))
    for (ReferenceEntry& e : renderReferenceScene(path, renderer, dir, write, profile)) entries.push_back(std::move(e));
  if (write) writeReferenceManifest(dir, entries, profile);
  return entries;
}

int reportReferences(const std::vector<ReferenceEntry>& entries, const std::string& dir, bool write, const std::string& profile) {
  // Matched by (scene, method), so a new method or scene shows up as new images while the
  // existing ones are still compared hash for hash.
  int bad = 0, fresh = 0, same = 0;
  std::map<std::pair<std::string, std::string>, std::string> expected;
  if (!write)
    for (const ReferenceEntry& m : readManifest(referenceManifest(dir, profile))) expected[{m.scene, m.method}] = m.hash;
  for (const ReferenceEntry& e : entries) {
    if (write) continue;
    const auto it = expected.find({e.scene, e.method});
    if (it == expected.end()) {
      std::printf("new (not in the manifest): %s %s\n", e.scene.c_str(), e.method.c_str()), ++fresh;
      continue;
    }
    if (it->second != e.hash) std::printf("differs: %s %s\n", e.scene.c_str(), e.method.c_str()), ++bad;
    else ++same;
    expected.erase(it);
  }
  for (const auto& [key, hash] : expected)
    std::printf("missing (in the manifest, not rendered): %s %s\n", key.first.c_str(), key.second.c_str()), ++bad;
  if (!write && (bad || fresh)) std::printf("%d differ or are missing, %d are new, %d identical\n", bad, fresh, same);
  bad += fresh;
  std::printf("%s %zu reference %s\n", write ? "wrote" : (bad ? "FAILED:" : "identical:"), entries.size(),
              profile == "exact" ? "images" : "hashes");
  return bad ? 1 : 0;
}

std::vector<ReferenceEntry> readManifest(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot read the reference manifest");
  std::vector<ReferenceEntry> entries;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    ReferenceEntry e;
    if (!(fields >> e.scene >> e.method >> e.hash)) throw std::runtime_error(path + ": bad line '" + line + "'");
    entries.push_back(e);
  }
  return entries;
}

}  // namespace oitref::tools
