// DFAOIT's training: deterministic, and it learns.
#include <catch2/catch.hpp>

#include "tools/dfaoit_training.h"

using namespace oitref;
using namespace oitref::tools;

TEST_CASE("train-dfaoit: the same weights every run, and the loss falls", "[training]") {
  Renderer renderer(RendererOptions{2, 64});
  std::vector<Scene> scenes = dfaoitTrainingScenes();
  REQUIRE(scenes.size() == 16);
  scenes.resize(2);
  for (Scene& s : scenes) s.width = s.height = 48;
  const std::vector<DfaoitSample> samples = dfaoitDataset(scenes, renderer);
  REQUIRE(samples.size() > 500);
  for (const DfaoitSample& s : samples)
    for (int k = 0; k < 3; ++k) REQUIRE((s.target[k] >= 0 && s.target[k] <= 1));
  DfaoitTraining o;
  o.epochs = 30;
  o.batch = 256;
  std::vector<double> losses;
  const methods::DfaoitParameters a = trainDfaoit(samples, o, [&](int, double loss) { losses.push_back(loss); });
  const methods::DfaoitParameters b = trainDfaoit(samples, o, [](int, double) {});
  CHECK(a == b);
  REQUIRE(losses.size() == 30);
  CHECK(losses.back() < 0.5 * losses.front());
  o.seed = 2;
  CHECK(trainDfaoit(samples, o, [](int, double) {}) != a);
}

TEST_CASE("train-dfaoit: the weights header round-trips every bit", "[training]") {
  methods::DfaoitParameters p{};
  for (size_t i = 0; i < p.size(); ++i) p[i] = float(i) * 1e-3f - 0.3f + (i % 7 == 0 ? 1e-30f : 0.0f);
  const std::string header = dfaoitWeightsHeader(p, "test");
  // Every value is written as a hex float: parse them back.
  size_t at = header.find("= {\n"), n = 0;
  REQUIRE(at != std::string::npos);
  for (const char* c = header.c_str() + at + 4; *c && *c != '}';) {
    char* end = nullptr;
    const float v = std::strtof(c, &end);
    if (end == c) { ++c; continue; }
    REQUIRE(n < p.size());
    CHECK(v == p[n]);
    ++n;
    c = end;
  }
  CHECK(n == p.size());
}
