// `oitref compare A B`: how far image B is from image A (oitref/oit/metrics.h), as text or JSON, with
// optional error and FLIP heatmaps.
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "oitref/oit/metrics.h"
#include "tools/commands.h"
#include "oitref/oit/image_io.h"
#include "tools/number_parse.h"

namespace oitref::tools {
namespace {

struct CompareOptions {
  std::string reference, test, heatmap, flipMap;
  double threshold = 1.0 / 255.0, heatmapScale = 0, ppd = FlipOptions{}.pixelsPerDegree;
  bool json = false;
};

// A number option that must be finite and at least `least` (above it where `strictly`).
void requireNumber(const char* option, double v, double least, bool strictly) {
  if (std::isfinite(v) && v >= least && !(strictly && v == least)) return;
  char text[96];
  std::snprintf(text, sizeof text, "%s %g: must be a finite number %s %g", option, v, strictly ? "above" : "of at least", least);
  throw std::invalid_argument(text);
}

int runCompare(const CompareOptions& o) {
  requireNumber("--threshold", o.threshold, 0.0, false);
  requireNumber("--heatmap-scale", o.heatmapScale, 0.0, false);
  requireNumber("--ppd", o.ppd, 0.0, true);
  const ImageFile a = readImage(o.reference), b = readImage(o.test);
  if (a.image.width() != b.image.width() || a.image.height() != b.image.height())
    throw std::invalid_argument("the images differ in size: " + o.reference + " is " + std::to_string(a.image.width()) +
                                "x" + std::to_string(a.image.height()) + ", " + o.test + " is " +
                                std::to_string(b.image.width()) + "x" + std::to_string(b.image.height()));
  if (a.channels != b.channels)
    throw std::invalid_argument("the images differ in channel count: " + o.reference + " has " +
                                std::to_string(a.channels) + ", " + o.test + " has " + std::to_string(b.channels));
  const ImageDifference d = compareImages(a.image, b.image, o.threshold);
  const double above = d.pixels ? double(d.pixelsAbove) / double(d.pixels) : 0.0;
  const FlipResult f = flip(a.image, b.image, FlipOptions{o.ppd});
  if (o.json) {
    std::printf("{\"reference\": %s, \"test\": %s, \"width\": %d, \"height\": %d, \"channels\": %d, "
                "\"mse\": %s, \"rmse\": %s, \"psnr\": %s, \"mean_abs\": %s, \"max_abs\": %s, \"max_at\": [%d, %d], "
                "\"threshold\": %s, \"share_above\": %s, \"pixels_differing\": %zu, \"non_finite_pixels\": %zu, "
                "\"non_finite_differing\": %zu, \"differ\": %s, "
                "\"flip_mean\": %s, \"flip_max\": %s, \"flip_pixels_per_degree\": %s}\n",
                jsonString(o.reference).c_str(), jsonString(o.test).c_str(), a.image.width(), a.image.height(), a.channels,
                jsonNumber(d.mse).c_str(), jsonNumber(d.rmse).c_str(), jsonNumber(d.psnr).c_str(),
                jsonNumber(d.meanAbs).c_str(), jsonNumber(d.maxAbs).c_str(), d.maxX,
                d.maxY < 0 ? -1 : a.image.height() - 1 - d.maxY, jsonNumber(o.threshold).c_str(),
                jsonNumber(above).c_str(), d.pixelsDiffering, d.nonFinitePixels, d.nonFiniteDiffering,
                d.differs() ? "true" : "false", jsonNumber(f.mean).c_str(),
                jsonNumber(f.max).c_str(), jsonNumber(o.ppd).c_str());
  } else {
    std::printf("%s vs %s  %dx%d, %d channels (colour: the first %d)\n", o.reference.c_str(), o.test.c_str(),
                a.image.width(), a.image.height(), a.channels, std::min(a.channels, 3));
    // First: values that no error metric below can show.
    if (d.nonFiniteDiffering)
      std::printf("  NON-FINITE DIFFERENCES: %zu pixels (NaN or inf in one image where the other has another value)\n",
                  d.nonFiniteDiffering);
    std::printf("  MSE        %.6g\n  RMSE       %.6g\n  PSNR       %.4g dB\n  mean |Δ|   %.6g\n", d.mse, d.rmse, d.psnr,
                d.meanAbs);
    if (d.maxX >= 0)
      std::printf("  max |Δ|    %.6g at (%d, %d), top row 0\n", d.maxAbs, d.maxX, a.image.height() - 1 - d.maxY);
    else
      std::printf("  max |Δ|    0\n");
    std::printf("  above %.6g: %zu pixels (%.4f %%)\n  differing: %zu pixels\n", o.threshold, d.pixelsAbove,
                100.0 * above, d.pixelsDiffering);
    std::printf("  FLIP       mean %.6g, max %.6g (LDR, %.4g pixels per degree)\n", f.mean, f.max, o.ppd);
    if (d.nonFinitePixels) std::printf("  non-finite: %zu pixels (NaN or inf in either image; not in the sums)\n", d.nonFinitePixels);
    std::printf("  %s\n", d.differs() ? "differ (exit status 1)" : "agree (exit status 0)");
  }
  if (!o.heatmap.empty()) {
    const double scale = o.heatmapScale > 0 ? o.heatmapScale : (d.maxAbs > 0 ? d.maxAbs : 1.0);
    writeImage(o.heatmap, errorHeatmapWithLegend(a.image, b.image, scale));
    if (!o.json) std::printf("heatmap %s (white at |Δ| = %.6g)\n", o.heatmap.c_str(), scale);
  }
  if (!o.flipMap.empty()) {
    writeImage(o.flipMap, flipHeatmapWithLegend(f));
    if (!o.json) std::printf("FLIP map %s (white at 1)\n", o.flipMap.c_str());
  }
  return d.differs() ? 1 : 0;
}

}  // namespace

void addCompareCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand("compare", "How far image B is from image A: MSE, RMSE, PSNR, mean and max error, FLIP. "
                                                 "Exit status 0: no pixel above the threshold and no NaN or inf where the "
                                                 "other image has another value; 1: the images differ so; 2: an error");
  nonEmptyPath(cmd->add_option("a", o->reference, "Reference image (EXR, PNG, PFM, …)"))->required();
  nonEmptyPath(cmd->add_option("b", o->test, "Image to compare with it"))->required();
  cmd->add_option("--threshold", o->threshold, "Per-pixel error counted as 'above' (default 1/255)");
  nonEmptyPath(cmd->add_option("--heatmap", o->heatmap, "Write an error heatmap (PNG) here"));
  cmd->add_option("--heatmap-scale", o->heatmapScale, "Error shown as white (default: the max error)");
  nonEmptyPath(cmd->add_option("--flip-map", o->flipMap, "Write the FLIP error map (PNG) here"));
  cmd->add_option("--ppd", o->ppd, "FLIP's pixels per degree (default: a 0.7 m wide 4K monitor at 0.7 m)");
  cmd->add_flag("--json", o->json, "Print one JSON object");
  cmd->callback([o, &exitCode] { exitCode = runReportingErrors("compare", [&] { return runCompare(*o); }); });
}

}  // namespace oitref::tools
