// The one-call frame API (oitref/oit/frame.h) against what guards the reference images: each frame it
// renders must hash as reference/manifest.txt records for that scene and method (96×72, exact).
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "oitref/oit/frame.h"

namespace oitref::test {
namespace {

// "scene method" → hash, from the manifest's lines.
std::map<std::string, std::string> manifest() {
  std::ifstream in(OITREF_SOURCE_DIR "/reference/manifest.txt");
  std::map<std::string, std::string> hashes;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string scene, method, hash;
    fields >> scene >> method >> hash;
    hashes[scene + " " + method] = hash;
  }
  return hashes;
}

FrameRequest at96x72(const std::string& method, int threads) {
  FrameRequest r;
  r.method = method;
  r.width = 96, r.height = 72;
  r.threads = threads;
  return r;
}

}  // namespace

TEST_CASE("renderFrame: the reference manifest's bits, on any thread count", "[frame]") {
  const std::map<std::string, std::string> expected = manifest();
  for (const std::string scene : {"glass", "squares"})
    for (const std::string method : {"wboit", "abuffer", "dualpeel"}) {
      INFO(scene << " " << method);
      REQUIRE(expected.count(scene + " " + method));
      const Scene s = loadScene(OITREF_SOURCE_DIR "/scenes/" + scene + ".json");
      for (int threads : {1, 3}) CHECK(frameHash(renderFrame(s, at96x72(method, threads))) == expected.at(scene + " " + method));
    }
}

TEST_CASE("FrameRenderer: repeated frames keep their bits", "[frame]") {
  FrameRenderer frames(loadScene(OITREF_SOURCE_DIR "/scenes/veils.json"), at96x72("mboit", 2));
  CHECK(frames.scene().width == 96);
  CHECK(frames.method().info().name == "mboit");
  const std::string first = frameHash(frames.render());
  CHECK(frameHash(frames.render()) == first);
  CHECK(frameHash(frames.release()) == first);
  CHECK(manifest().at("veils mboit") == first);
}

TEST_CASE("FrameRenderer: bad requests are refused before anything is drawn", "[frame]") {
  const Scene s = loadScene(OITREF_SOURCE_DIR "/scenes/squares.json");
  FrameRequest r = at96x72("nosuch", 1);
  CHECK_THROWS_AS(FrameRenderer(s, r), std::invalid_argument);
  r = at96x72("wboit", 1);
  r.options = {{"weight", "nosuch"}};
  CHECK_THROWS_AS(FrameRenderer(s, r), std::invalid_argument);
  r = at96x72("wboit", 1);
  r.height = 0;
  CHECK_THROWS_WITH(FrameRenderer(s, r), Catch::Contains("give both sides"));
  r = at96x72("wboit", 1);
  r.width = 16385;
  CHECK_THROWS_WITH(FrameRenderer(s, r), Catch::Contains("at most 16384"));
  r = at96x72("abuffer", 1);
  r.memoryLimit = 1000;
  CHECK_THROWS_AS(FrameRenderer(s, r), std::runtime_error);
}

}  // namespace oitref::test
