#include "glcheck/scene_check.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include "glcheck/gl_methods.h"
#include "oitref/oit/frame.h"
#include "oitref/oit/image_io.h"
#include "tools/suite.h"

namespace oitref::glcheck {
namespace {

// Heatmaps share one scale so methods can be compared by eye: white at 16 RGBA8 steps.
constexpr double kHeatmapScale = 16.0 / 255.0;

double shareBitEqual(const Image& a, const Image& b) {
  const size_t texels = size_t(a.width()) * size_t(a.height()), bytes = a.bytesPerTexel();
  size_t equal = 0;
  for (size_t i = 0; i < texels; ++i) equal += std::memcmp(&a.bytes()[i * bytes], &b.bytes()[i * bytes], bytes) == 0;
  return texels ? double(equal) / double(texels) : 1.0;
}

std::string percent(double share) {
  char text[16];
  std::snprintf(text, sizeof text, "%.2f %%", 100.0 * share);
  return text;
}

void printHeader(std::ostream& out, const std::string& scene, int w, int h, const Profile& profile,
                 const SceneCheckOptions& o) {
  char line[256];
  if (o.tolerance == 0.0 && o.minShare == 1.0)
    std::snprintf(line, sizeof line, "scene %s  %dx%d  oitref profile %s  bit-exact: every pixel and attachment equal\n",
                  scene.c_str(), w, h, profile.name.c_str());
  else
    std::snprintf(line, sizeof line, "scene %s  %dx%d  oitref profile %s  tolerance %.3g (%.2f RGBA8 steps), pass at ≥ %s\n",
                  scene.c_str(), w, h, profile.name.c_str(), o.tolerance, o.tolerance * 255.0, percent(o.minShare).c_str());
  out << line;
  out << "  method   RGBA8: RMSE     max       ≤ tol     equal    RGBA32F: RMSE  max        attachments bit-equal\n";
}

void printRow(std::ostream& out, const SceneCheckRow& r) {
  char line[512];
  std::string attachments;
  for (const auto& [name, share] : r.attachmentsBitEqual) attachments += " " + name + " " + percent(share);
  const ImageDifference& p = r.presented;
  std::snprintf(line, sizeof line, "  %-8s %12.3g %9.3g %9s %9s %14.3g %10.3g %s%s\n", r.method.c_str(), p.rmse, p.maxAbs,
                percent(p.shareWithin()).c_str(), percent(1.0 - double(p.pixelsDiffering) / double(p.pixels)).c_str(),
                r.analysis.rmse, r.analysis.maxAbs, attachments.c_str(), r.pass ? "" : "   FAIL");
  out << line;
  if (p.nonFinitePixels || r.analysis.nonFinitePixels)
    out << "           non-finite pixels: RGBA8 " << p.nonFinitePixels << ", RGBA32F " << r.analysis.nonFinitePixels << "\n";
}

// Side by side, per method: min and median of wall and process CPU time, and oitref's cost as a
// multiple of the driver's (median CPU and median wall), next to the bits it was timed on.
void printTimings(std::ostream& out, const std::vector<SceneCheckRow>& rows, const SceneCheckOptions& o, int threads) {
  char line[512];
  std::snprintf(line, sizeof line,
                "  timing: %d runs each, alternated, after a warm run; %d thread(s) each; both reuse their "
                "attachments between runs (oitref: a pool; GL: one frame, then glFinish)\n", o.timeRuns, threads);
  out << line;
  std::snprintf(line, sizeof line, "  %-8s %11s %9s %11s %12s %9s %11s %9s %6s %8s %7s   %s\n", "method", "oitref ms",
                "wall med", "CPU med", "GL ms", "wall med", "CPU med", "CPU ×", "wall ×", "pairs ×", "wall", "oitref sha256 (frame)");
  out << "  (oitref ms and GL ms: minimum wall time; CPU × and wall ×: the ratio of the medians; pairs ×: the median of\n"
         "  each run's ratio, oitref's frame over the GL frame right after it, CPU then wall)\n" << line;
  for (const SceneCheckRow& r : rows) {
    if (!r.timing) continue;
    const TimingStats &a = r.timing->oitref, &b = r.timing->gl;
    std::snprintf(line, sizeof line, "  %-8s %11.2f %9.2f %11.2f %12.2f %9.2f %11.2f %9.2f %6.2f %8.2f %7.2f   %s\n",
                  r.method.c_str(), a.minWallMs, a.medianWallMs, a.medianCpuMs, b.minWallMs, b.medianWallMs, b.medianCpuMs,
                  a.medianCpuMs / b.medianCpuMs, a.medianWallMs / b.medianWallMs, r.timing->pairedCpuRatio,
                  r.timing->pairedWallRatio, r.timing->sha256.substr(0, 16).c_str());
    out << line;
  }
  // Per pass: medians over the runs, summed per kind over a frame (×N: N passes of that kind).
  static const double bandwidth = measureMemoryBandwidth();  // GB/s, measured once per process
  std::snprintf(line, sizeof line,
                "  passes, median ms (oitref: steady clock per pass; GL: GL_TIME_ELAPSED timer queries)\n"
                "  memory bandwidth (one thread, memcpy of 256 MiB, bytes read + written): %.1f GB/s; a composite\n"
                "  reads every attachment once and reads and writes the presented targets: its floor is given\n",
                bandwidth);
  out << line;
  auto list = [](const std::vector<PassTiming>& passes) {
    std::string s;
    char item[128];
    for (const PassTiming& p : passes) {
      std::snprintf(item, sizeof item, "%s%s %.2f", s.empty() ? "" : ", ", p.kind.c_str(), p.medianMs);
      s += item;
      if (p.perFrame > 1) s += " (×" + std::to_string(p.perFrame) + ")";
    }
    return s;
  };
  for (const SceneCheckRow& r : rows) {
    if (!r.timing) continue;
    const auto& passes = r.timing->oitrefPasses;
    const bool composites = std::any_of(passes.begin(), passes.end(), [](const PassTiming& p) { return p.kind == "composite"; });
    line[0] = '\0';
    if (composites)
      std::snprintf(line, sizeof line, " (composite floor %.2f ms)", r.timing->compositeTrafficBytes / (bandwidth * 1e6));
    out << "  " << r.method << line << "\n    oitref: " << list(r.timing->oitrefPasses)
        << "\n    GL:     " << list(r.timing->glPasses) << "\n";
  }
}

}  // namespace

SceneCheckOptions resolvedSceneCheckOptions(const SceneCheckOptions& options, bool* bitExact) {
  SceneCheckOptions o = options;
  const bool wholePipeline = parseProfile(o.profile).raster == Rasterization::Llvmpipe;
  if (o.tolerance < 0.0) o.tolerance = wholePipeline ? 0.0 : 1.5 / 255.0;
  if (o.minShare < 0.0) o.minShare = wholePipeline ? 1.0 : 0.99;
  if (bitExact) *bitExact = o.tolerance == 0.0 && o.minShare == 1.0;
  return o;
}

std::vector<SceneCheckRow> runSceneCheck(const GlContext& context, const SceneCheckOptions& given, std::ostream& out) {
  bool bitExact = false;
  const SceneCheckOptions o = resolvedSceneCheckOptions(given, &bitExact);
  const Profile profile = parseProfile(o.profile);
  const std::vector<std::string> methodNames = o.methods.empty() ? glMethodNames() : o.methods;
  for (const std::string& m : methodNames)
    if (!findGlMethod(m)) {
      std::string valid;
      for (const std::string& n : glMethodNames()) valid += (valid.empty() ? "" : ", ") + n;
      throw std::invalid_argument("method '" + m + "' has no GL version (valid: " + valid + ")");
    }
  if (!o.heatmaps.empty()) std::filesystem::create_directories(o.heatmaps);
  Renderer renderer(RendererOptions{.threads = o.threads});
  std::vector<SceneCheckRow> rows;
  for (const std::string& path : o.scenes) {
    Scene scene = loadScene(path, o.memoryLimit);
    if (o.width > 0) scene.width = o.width, scene.height = o.height;
    const SceneFrames frames(std::move(scene), renderer, profile, o.memoryLimit);
    const FrameContext frame = frames.context();
    const std::string sceneName = tools::sceneName(path);
    printHeader(out, sceneName, frames.scene().width, frames.scene().height, profile, o);
    const size_t firstRow = rows.size();
    for (const std::string& name : methodNames) {
      const std::unique_ptr<Method> method = makeMethod(name, o.methodOptions);
      const MethodOptions options(method->info(), o.methodOptions);
      const FrameResult ours = frames.render(*method);
      GlFrame gl(context, frame, method->attachments());
      std::string presentedName;
      try {
        presentedName = findGlMethod(name)(gl, options);
      } catch (const std::invalid_argument& e) {  // a frame the method's GL version cannot draw
        throw std::invalid_argument(path + ": " + e.what());
      }
      const Image glPresented = gl.read(presentedName), glAnalysis = gl.read("analysis");
      SceneCheckRow row;
      row.scene = sceneName;
      row.method = name;
      row.presented = compareImages(glPresented, ours.final8, o.tolerance);
      row.analysis = compareImages(glAnalysis, ours.finalFloat, o.tolerance);
      for (const auto& [attachment, image] : ours.dump)
        row.attachmentsBitEqual.emplace_back(attachment, shareBitEqual(gl.read(attachment), image));
      row.pass = row.presented.shareWithin() >= o.minShare && row.presented.nonFinitePixels == 0;
      // Bit-exact: the RGBA32F copy and every declared attachment as well.
      if (bitExact) {
        row.pass = row.pass && row.analysis.pixelsDiffering == 0;
        for (const auto& [attachment, share] : row.attachmentsBitEqual) row.pass = row.pass && share == 1.0;
      }
      printRow(out, row);
      if (!o.heatmaps.empty()) {
        const std::filesystem::path base = std::filesystem::path(o.heatmaps) / (sceneName + "_" + name);
        writeImage(base.string() + "_gl.png", glPresented);
        writeImage(base.string() + "_oitref.png", ours.final8);
        writeImage(base.string() + "_error.png", errorHeatmap(glPresented, ours.final8, kHeatmapScale));
      }
      if (o.timeRuns > 0) row.timing = timeMethod(context, frame, *method, findGlMethod(name), options, o.timeRuns);
      rows.push_back(std::move(row));
    }
    if (o.timeRuns > 0)
      printTimings(out, std::vector<SceneCheckRow>(rows.begin() + ptrdiff_t(firstRow), rows.end()), o, renderer.threads());
    out << "\n";
  }
  if (!o.heatmaps.empty())
    out << "images in " << o.heatmaps << "/<scene>_<method>_{gl,oitref,error}.png (error: white at "
        << kHeatmapScale * 255.0 << " RGBA8 steps, green where non-finite)\n";
  return rows;
}

}  // namespace oitref::glcheck
