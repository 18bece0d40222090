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
  // Run as a job of a plan (oitref job): its index and the node that timed it; -1 and "" when the
  // whole study ran in one process.
  int job = -1;
  std::string node;
};

struct StudyScene {
  std::string name;
  int width = 0, height = 0;
  uint64_t fragments = 0;
  int depthComplexityMax = 0;
  // The A-buffer checked against the ray cast, an independent ground truth (hasRaycast: the
  // ray cast's row was among the variants rendered).
  double raycastRmse = 0, raycastMax = 0, raycastShareWithin = 0;
  bool hasRaycast = false;
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
  double totalSeconds = 0;  // run as jobs: the sum of the jobs' times
  // Run as jobs of a plan (oitref collect): how many, and the nodes that ran them (sorted); 0 and
  // empty for a study in one process. threads is then the jobs' count where they all had the same.
  int jobs = 0;
  std::vector<std::string> nodes;
};

// Progress: (what, index of the item, number of items).
using StudyProgress = std::function<void(const std::string&, int, int)>;

// "[ 12/210] 00:07 ballpark: wboit weight=mb7" on stderr: a line per item, or one line rewritten
// in place when stderr is a terminal; nothing when quiet.
StudyProgress studyProgressPrinter(bool quiet);

// The configurations the options ask for, in studyVariants()'s order (the A-buffer first); an
// unknown method in options.methods fails here, with a suggestion.
std::vector<StudyVariant> studyVariantsFor(const StudyOptions& options);

// One scene of the study, for `variants` (studyVariantsFor's list, or a run of it): renders,
// times and measures them and writes their images (and error heatmaps) under
// options.outDir/<scene>/. Every row is measured against the A-buffer at its defaults; where
// `variants` does not start with it, it is rendered first, untimed, for the truth alone (frames
// are the same bits in every process, so a job of a plan measures what the whole study would).
// `firstItem` numbers the progress lines; the process's first item gets five warm-up frames.
StudyScene runStudyScene(const StudyOptions& options, const std::string& scenePath, const std::vector<StudyVariant>& variants,
                         Renderer& renderer, const StudyProgress& progress, int firstItem, int items);

// Renders, times and measures everything; writes the images (and their error heatmaps) under
// options.outDir/<scene>/.
StudyResult runStudy(const StudyOptions& options, Renderer& renderer, const StudyProgress& progress);

}  // namespace oitref::tools
