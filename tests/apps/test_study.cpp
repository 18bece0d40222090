// oitref study: its numbers recomputed independently from the renders they claim to measure, the
// Pareto front by hand, and the written files parsed back.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "oitref/oit/metrics.h"
#include "temp_files.h"
#include "oitref/oit/image_io.h"
#include "tools/study.h"
#include "tools/study_report.h"

using namespace oitref;
using namespace oitref::tools;

namespace {

StudyRow row(const std::string& method, double ms, double rmse) {
  StudyRow r;
  r.variant.method = method;
  r.ms = ms, r.rmse = rmse;
  return r;
}

// A study of the squares scene at 64×48 into a fresh folder.
StudyOptions squaresStudy(const std::string& folder, int runs, std::vector<std::string> methods) {
  StudyOptions o;
  o.scenes = {OITREF_SOURCE_DIR "/scenes/squares.json"};
  o.outDir = test::tempFolder(folder).string();
  o.width = 64, o.height = 48;
  o.runs = runs;
  o.methods = std::move(methods);
  return o;
}

}  // namespace

TEST_CASE("Study: the Pareto front by hand", "[study]") {
  // (ms, RMSE): b is dominated by a (slower and worse), d by c, e ties c in error but is slower;
  // f is exact and slowest, still on the front; g is exact but slower than f.
  const std::vector<StudyRow> rows = {row("truth", 12, 0), row("a", 1, 0.1),  row("b", 2, 0.2),
                                      row("c", 3, 0.01),   row("d", 4, 0.05), row("e", 5, 0.01),
                                      row("f", 9, 0),      row("g", 10, 1e-9)};
  CHECK(paretoFront(rows, 1e-6) == std::vector<size_t>{1, 3, 6});
  // The ground truth is a method too: when it is the fastest exact one, it ends the front.
  std::vector<StudyRow> fast = rows;
  fast[0].ms = 8;
  CHECK(paretoFront(fast, 1e-6) == std::vector<size_t>{1, 3, 0});
}

TEST_CASE("Study: every row's numbers are those of its own render against the A-buffer", "[study]") {
  const StudyOptions o = squaresStudy("oitref_study_test", 2, {"wboit", "peel"});
  const std::filesystem::path out = o.outDir;
  Renderer renderer(RendererOptions{2, 64});
  int calls = 0, lastTotal = 0;
  const StudyResult result = runStudy(o, renderer, [&](const std::string&, int i, int n) {
    CHECK(i == ++calls);
    lastTotal = n;
  });
  REQUIRE(result.scenes.size() == 1);
  const StudyScene& s = result.scenes[0];
  CHECK(calls == lastTotal);
  CHECK(int(s.rows.size()) == calls);
  // The A-buffer first (its variants too), the ray cast always, only the methods asked for.
  REQUIRE(s.rows[0].variant.method == "abuffer");
  CHECK(s.rows[0].rmse == 0);
  for (const StudyRow& r : s.rows) {
    CHECK((r.variant.method == "abuffer" || r.variant.method == "raycast" || r.variant.method == "wboit" ||
           r.variant.method == "peel"));
    CHECK(r.runMs.size() == 2);
    CHECK(std::filesystem::exists(out / r.image));
    CHECK(std::filesystem::exists(out / r.heatmap));
  }
  CHECK(s.raycastRmse < 1e-6);

  // Recompute one row from scratch.
  Scene scene = loadScene(o.scenes[0]);
  scene.width = 64, scene.height = 48;
  const SceneGeometry geometry = buildSceneGeometry(scene);
  const FrameContext context{scene, geometry, 64, 48, exactProfile(), renderer};
  const FrameResult truth = makeMethod("abuffer")->render(context);
  const auto mb7 = std::find_if(s.rows.begin(), s.rows.end(), [](const StudyRow& r) {
    return r.variant.method == "wboit" && r.variant.options.count("weight") && r.variant.options.at("weight") == "mb7";
  });
  REQUIRE(mb7 != s.rows.end());
  std::unique_ptr<Method> method = makeMethod("wboit", mb7->variant.options);
  const FrameResult frame = method->render(context);
  const ImageDifference d = compareImages(frame.finalFloat, truth.finalFloat, 0);
  CHECK(mb7->rmse == d.rmse);
  CHECK(mb7->maxError == d.maxAbs);
  CHECK(mb7->flip == flip(truth.finalFloat, frame.finalFloat).mean);
  CHECK(mb7->bytesPerPixel == method->bytesPerPixel());
  CHECK(mb7->fragmentsShaded == frame.fragmentsShaded());
  CHECK(mb7->fragmentsPerSecond == Approx(double(frame.fragmentsShaded()) / (mb7->ms / 1000)));
  // Its files (written by the renderer's workers after the scene's timed frames): the image's
  // 8-bit texels, and the heatmap of this frame against the truth.
  const Image written = readImage((out / mb7->image).string()).image;
  REQUIRE(written.width() == 64);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) REQUIRE(written.fetch(x, y) == frame.final8.fetch(x, y));
  const Image heatmap = errorHeatmap(truth.finalFloat, frame.finalFloat, o.heatmapScale);
  const Image writtenHeatmap = readImage((out / mb7->heatmap).string()).image;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) REQUIRE(writtenHeatmap.fetch(x, y) == heatmap.fetch(x, y));

  // The files parse back with the same numbers.
  const nlohmann::json json = nlohmann::json::parse(studyJson(result));
  REQUIRE(json["scenes"].size() == 1);
  REQUIRE(json["scenes"][0]["rows"].size() == s.rows.size());
  const auto& first = json["scenes"][0]["rows"][1];
  CHECK(first["method"] == s.rows[1].variant.method);
  CHECK(first["rmse"].get<double>() == Approx(s.rows[1].rmse).epsilon(1e-8).margin(1e-300));
  std::istringstream csv(studyCsv(result));
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  CHECK(lines == int(s.rows.size()) + 1);
  const std::string html = studyHtml(result);
  CHECK(html.find("<svg class=scatter") != std::string::npos);
  CHECK(html.find("id=\"scene-squares\"") != std::string::npos);
  CHECK(html.find("id=memory") != std::string::npos);
}

TEST_CASE("Study: the peeling rows say how far they peeled, dual peeling's too", "[study]") {
  const StudyOptions o = squaresStudy("oitref_study_peeling_test", 1, {"peel", "dualpeel"});
  Renderer renderer(RendererOptions{2, 64});
  const StudyResult result = runStudy(o, renderer, [](const std::string&, int, int) {});
  REQUIRE(result.scenes.size() == 1);
  const StudyScene& s = result.scenes[0];
  REQUIRE(s.depthComplexityMax > 0);  // from the A-buffer's lists
  int peel = 0, dual = 0;
  for (const StudyRow& r : s.rows) {
    INFO(r.variant.method << " " << r.variant.label());
    if (r.variant.method == "peel") {
      ++peel;
      // Front to back, one layer a pass: all of them when the passes reach the deepest pixel.
      const int passes = r.variant.options.count("passes") ? std::stoi(r.variant.options.at("passes")) : 32;
      if (passes >= s.depthComplexityMax) CHECK(r.note == "peeled " + std::to_string(s.depthComplexityMax) + " layers (all)");
      else CHECK(r.note == "peeled " + std::to_string(passes) + " layers (more remain)");
    }
    if (r.variant.method == "dualpeel") {
      ++dual;
      // A front and a back layer a pass, and the pass that finds nothing ends it.
      const int needed = (s.depthComplexityMax + 1) / 2 + 1;
      const int passes = r.variant.options.count("passes") ? std::stoi(r.variant.options.at("passes")) : 64;
      int drawn = 0;
      char done[32] = {};
      REQUIRE(std::sscanf(r.note.c_str(), "peeled in %d passes (%31[^)])", &drawn, done) == 2);
      if (passes >= needed) {
        CHECK(std::string(done) == "all");
        CHECK(drawn >= (s.depthComplexityMax + 1) / 2);
        CHECK(drawn <= needed);
      } else if (passes < (s.depthComplexityMax + 1) / 2) {
        CHECK(std::string(done) == "more remain");
        CHECK(drawn == passes);
      }
    }
  }
  CHECK(peel > 0);
  CHECK(dual > 0);
}

TEST_CASE("Study: unknown methods are refused before anything renders", "[study]") {
  StudyOptions o;
  o.scenes = {OITREF_SOURCE_DIR "/scenes/squares.json"};
  o.outDir = test::tempFolder("oitref_study_bad").string();
  o.methods = {"wbiot"};
  Renderer renderer(RendererOptions{1, 64});
  int calls = 0;
  CHECK_THROWS_WITH(runStudy(o, renderer, [&](const std::string&, int, int) { ++calls; }), Catch::Contains("wboit"));
  CHECK(calls == 0);
}
