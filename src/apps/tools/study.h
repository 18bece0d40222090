// `oitref study`: every method and the variants that matter, on each scene, timed and measured
// against the ground truth; the numbers behind the HTML report (study_report.h).
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "oitref/oit/method.h"

namespace oitref::tools {

// One configuration the study renders: a method with some options set.
struct StudyVariant {
  std::string method;
  std::map<std::string, std::string> options;  // only the ones that differ from the defaults
  std::string label() const;                    // "default" or "accum=rgba16f weight=mb7"
  std::string slug() const;                     // file-name safe: "wboit_accum-rgba16f_weight-mb7"
};

// Every registered method at its defaults (in registry order, the A-buffer first), each followed
// by the variants it names (MethodInfo::studyVariants: accumulation formats, WBOIT weights, MBOIT
// bias/warp/format, peel pass counts 1…16, …).
std::vector<StudyVariant> studyVariants();

struct StudyRow {
  StudyVariant variant;
  double ms = 0;                   // median wall-clock time of render() over the timed runs
  std::vector<double> runMs;       // every timed run
  uint64_t fragmentsShaded = 0;    // per frame
  double fragmentsPerSecond = 0;
  int bytesPerPixel = 0;           // the declared attachments
  int passes = 0;                  // pipeline passes of one frame
  double rmse = 0, psnr = 0, maxError = 0;  // RGB of the RGBA32F result against the A-buffer's
  double flip = 0;                 // mean LDR ꟻLIP of the RGBA32F result against the A-buffer's (as displayed:
                                   // clamped to [0, 1], read as sRGB)
  size_t nonFinitePixels = 0;
  std::string note;                // how far peeling got (FrameStats), worth a glance
  std::string image, heatmap;      // paths relative to the report folder
};

struct StudyScene {
  std::string name;
  int width = 0, height = 0;
  uint64_t fragments = 0;
  int depthComplexityMax = 0;
  // The A-buffer checked against the ray cast, an independent ground truth.
  double raycastRmse = 0, raycastMax = 0, raycastShareWithin = 0;
  std::vector<StudyRow> rows;  // rows[0] is the A-buffer
};

struct StudyOptions {
  std::vector<std::string> scenes;
  std::string outDir;
  int width = 0, height = 0;  // 0: each scene's own
  int runs = 5;               // timed runs after one warm-up (study.cpp: the warm-up of a slow variant counts)
  double heatmapScale = 0.25;
  Profile profile = exactProfile();
  uint64_t memoryLimit = UINT64_MAX;
  std::vector<std::string> methods;  // empty: all
};

struct StudyResult {
  std::vector<StudyScene> scenes;
  int threads = 0, runs = 0;
  double heatmapScale = 0;
  std::string profile;
  double totalSeconds = 0;
};

// Progress: (what, index of the item, number of items).
using StudyProgress = std::function<void(const std::string&, int, int)>;

// Renders, times and measures everything; writes the images (and their error heatmaps) under
// options.outDir/<scene>/.
StudyResult runStudy(const StudyOptions& options, Renderer& renderer, const StudyProgress& progress);

}  // namespace oitref::tools
