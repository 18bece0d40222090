#include "tools/study.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "oitref/oit/metrics.h"
#include "oitref/oit/frame.h"
#include "oitref/oit/image_io.h"
#include "tools/suite.h"

namespace oitref::tools {
namespace fs = std::filesystem;

std::string StudyVariant::label() const {
  if (options.empty()) return "default";
  std::string s;
  for (const auto& [k, v] : options) s += (s.empty() ? "" : " ") + k + "=" + v;
  return s;
}

std::string StudyVariant::slug() const {
  std::string s = method;
  for (const auto& [k, v] : options) s += "_" + k + "-" + v;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '-';
  return s;
}

std::vector<StudyVariant> studyVariants() {
  // Each method at its defaults, then the variants it names (MethodInfo::studyVariants); the
  // A-buffer first: it is every other row's reference.
  std::vector<MethodInfo> methods = allMethods();
  std::stable_partition(methods.begin(), methods.end(), [](const MethodInfo& m) { return m.name == "abuffer"; });
  std::vector<StudyVariant> out;
  for (const MethodInfo& info : methods) {
    out.push_back({info.name, {}});
    for (const OptionValues& options : info.studyVariants) out.push_back({info.name, options});
  }
  return out;
}

namespace {

// Peeling's note: the layers peeled (front to back, one a pass) or the passes drawn (dual
// peeling, a front and a back layer a pass), and whether any remain.
std::string noteOf(const FrameStats& stats) {
  if (!stats.allLayersPeeled) return "";
  const std::string done = *stats.allLayersPeeled ? " (all)" : " (more remain)";
  if (stats.layersPeeled) return "peeled " + std::to_string(*stats.layersPeeled) + " layers" + done;
  if (stats.peelingPasses) return "peeled in " + std::to_string(*stats.peelingPasses) + " passes" + done;
  return "";
}

// Renders one variant: `warmups` untimed frames, then `runs` timed frames, whose bits must all
// agree. Each frame reuses the previous one's attachments (a pool of this variant's: at most one
// frame's worth is kept), as an application would. The bits are compared with the first frame's
// whole (a hash of each frame cost the study 15 s of one core in SHA-256, to the same verdict).
// A single warm-up frame that took kSlowFrameMs or more counts as the first timed run: what it
// pays beyond the others is taking fresh attachments (under a millisecond at the study's sizes),
// so the study's slowest variants render five frames, not six.
constexpr double kSlowFrameMs = 100.0;
FrameResult timedRender(Method& method, const SceneFrames& frames, int warmups, int runs, std::vector<double>& runMs) {
  AttachmentPool pool;
  const FrameContext context = frames.context(&pool);
  FrameResult frame;
  auto render = [&] {  // the next frame into `frame`, its time in ms
    pool.recycle(std::move(frame));
    const auto t0 = std::chrono::steady_clock::now();
    frame = method.render(context);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  const double firstMs = render();
  if (warmups == 1 && firstMs >= kSlowFrameMs) runMs.push_back(firstMs);
  for (int i = 1; i < warmups; ++i) render();
  const std::vector<uint8_t> first8 = frame.final8.bytes(), firstFloat = frame.finalFloat.bytes();
  while (int(runMs.size()) < runs) {
    runMs.push_back(render());
    if (frame.final8.bytes() != first8 || frame.finalFloat.bytes() != firstFloat)
      throw std::logic_error(method.info().name + ": frames of the same scene differ between runs (a determinism bug)");
  }
  return frame;
}

bool wanted(const StudyOptions& o, const std::string& method) {
  return method == "abuffer" || method == "raycast" || o.methods.empty() ||
         std::find(o.methods.begin(), o.methods.end(), method) != o.methods.end();
}


// What a rendered variant leaves for the analysis: its row (timed, not yet measured) and the two
// presented images the measures and files need.
struct PendingRow {
  size_t row = 0;
  Image final8, finalFloat;
};

// The measures of each pending row against the scene's truth, and its image and heatmap files:
// per row on the renderer's workers, after the timed frames (so that they never share the
// machine with a clock). Each row's figures are its own computation alone, so the report is the
// same for any thread count; one thread did this for 15–20 s of the main command's study.
void analyse(std::vector<PendingRow>& pending, StudyScene& s, const Image& truth, const FlipReference& flipTruth,
             const StudyOptions& o, Renderer& renderer) {
  renderer.parallelFor(pending.size(), [&](size_t i) {
    const PendingRow& p = pending[i];
    StudyRow& row = s.rows[p.row];
    const ImageDifference d = compareImages(p.finalFloat, truth, 1.0 / 255);
    row.rmse = d.rmse, row.psnr = d.psnr, row.maxError = d.maxAbs, row.nonFinitePixels = d.nonFinitePixels;
    row.flip = flipTruth.compare(p.finalFloat).mean;
    if (row.variant.method == "raycast" && row.variant.options.empty())
      s.raycastRmse = d.rmse, s.raycastMax = d.maxAbs, s.raycastShareWithin = d.shareWithin(), s.hasRaycast = true;
    writeImage((fs::path(o.outDir) / row.image).string(), p.final8);
    writeImage((fs::path(o.outDir) / row.heatmap).string(), errorHeatmap(truth, p.finalFloat, o.heatmapScale));
  });
  pending.clear();
}

// Rendered frames wait for their analysis until they hold this much (then the batch is analysed
// before the next variant renders), so that a study at 4K does not keep a scene's every frame.
constexpr size_t kPendingBytes = size_t(256) << 20;

}  // namespace

StudyProgress studyProgressPrinter(bool quiet) {
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

std::vector<StudyVariant> studyVariantsFor(const StudyOptions& o) {
  for (const std::string& m : o.methods) makeMethod(m);  // unknown names fail here, with a suggestion
  std::vector<StudyVariant> variants;
  for (const StudyVariant& v : studyVariants())
    if (wanted(o, v.method)) variants.push_back(v);
  return variants;
}

StudyScene runStudyScene(const StudyOptions& o, const std::string& path, const std::vector<StudyVariant>& variants,
                         Renderer& renderer, const StudyProgress& progress, int item, int items) {
  Scene scene = loadScene(path, o.memoryLimit);
  if (o.width > 0) scene.width = o.width, scene.height = o.height;
  const SceneFrames frames(std::move(scene), renderer, o.profile, o.memoryLimit);
  StudyScene s;
  s.name = sceneName(path);
  s.width = frames.scene().width, s.height = frames.scene().height;
  fs::create_directories(fs::path(o.outDir) / s.name);
  Image truth;
  std::unique_ptr<FlipReference> flipTruth;  // the truth prepared once for ꟻLIP
  // The A-buffer at its defaults: the ground truth, and the scene's fragment counts.
  auto takeTruth = [&](const FrameResult& frame) {
    s.fragments = frame.stats.fragments.value_or(0);
    s.depthComplexityMax = int(frame.stats.depthComplexityMax.value_or(0));
    truth = frame.finalFloat;
    flipTruth = std::make_unique<FlipReference>(truth);
  };
  const StudyVariant groundTruth{"abuffer", {}};
  const bool truthIsRow = !variants.empty() && variants.front().method == groundTruth.method && variants.front().options.empty();
  if (!truthIsRow) {
    std::unique_ptr<Method> method = makeMethod(groundTruth.method);
    frames.checkMemoryOf(*method);
    takeTruth(frames.render(*method));
  }
  std::vector<PendingRow> pending;
  size_t pendingBytes = 0;
  for (const StudyVariant& v : variants) {
    progress(s.name + ": " + v.method + " " + v.label(), item, items);
    std::unique_ptr<Method> method = makeMethod(v.method, v.options);
    frames.checkMemoryOf(*method);
    StudyRow row;
    row.variant = v;
    // The process's very first frames also warm it (thread pool, allocator, caches): measured
    // alone, the first configuration ran 2.3 times slower after a single warm-up.
    FrameResult frame = timedRender(*method, frames, item == 1 ? 5 : 1, o.runs, row.runMs);
    ++item;
    std::vector<double> sorted = row.runMs;
    std::sort(sorted.begin(), sorted.end());
    row.ms = sorted[sorted.size() / 2];
    if (truthIsRow && s.rows.empty()) takeTruth(frame);
    row.fragmentsShaded = frame.fragmentsShaded();
    row.fragmentsPerSecond = row.ms > 0 ? double(row.fragmentsShaded) / (row.ms / 1000) : 0;
    row.bytesPerPixel = method->bytesPerPixel();
    row.passes = int(frame.passes.size());
    row.note = noteOf(frame.stats);
    row.image = s.name + "/" + v.slug() + ".png";
    row.heatmap = s.name + "/" + v.slug() + "_error.png";
    s.rows.push_back(row);
    pendingBytes += frame.final8.bytes().size() + frame.finalFloat.bytes().size();
    pending.push_back({s.rows.size() - 1, std::move(frame.final8), std::move(frame.finalFloat)});
    if (pendingBytes >= kPendingBytes) analyse(pending, s, truth, *flipTruth, o, renderer), pendingBytes = 0;
  }
  analyse(pending, s, truth, *flipTruth, o, renderer);
  return s;
}

StudyResult runStudy(const StudyOptions& o, Renderer& renderer, const StudyProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<StudyVariant> variants = studyVariantsFor(o);
  StudyResult result;
  result.threads = renderer.threads(), result.runs = o.runs, result.heatmapScale = o.heatmapScale;
  result.profile = o.profile.name;
  const int items = int(o.scenes.size() * variants.size());
  for (size_t i = 0; i < o.scenes.size(); ++i)
    result.scenes.push_back(runStudyScene(o, o.scenes[i], variants, renderer, progress, int(i * variants.size()) + 1, items));
  result.totalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace oitref::tools
