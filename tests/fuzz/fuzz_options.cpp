// Text → the option parsers of the command line: lines of the form "method NAME", "set KEY=VALUE"
// (as --set), "profile SPEC" (as --profile), "size WxH" (as --size), "memory TEXT" (as
// --memory-limit). Every parser must end in std::invalid_argument on bad values; a method whose
// options were accepted renders a tiny frame of a built-in scene (or refuses it with a
// std::runtime_error that names the limit, as the command line reports it), whose pixels must not be NaN
// unless the method says its pixels can be (MethodInfo::nonFiniteWhen; meshkin3's 1/α at the
// particles' α = 0 corners). For any other method a NaN here is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "oitref/oit/method.h"
#include "oitref/core/profile.h"
#include "oitref/core/renderer.h"
#include "oitref/oit/scene.h"
#include "oitref/oit/scene_geometry.h"
#include "tools/commands.h"
#include "tools/number_parse.h"

namespace {

const oitref::Scene& tinyScene() {
  static const oitref::Scene scene = [] {
    oitref::Scene s = oitref::loadScene(OITREF_SOURCE_DIR "/scenes/squares.json");
    s.width = 8, s.height = 6;
    return s;
  }();
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::string line, method = "wboit";
  std::vector<std::string> sets;
  oitref::Profile profile = oitref::exactProfile();
  try {
    while (std::getline(in, line)) {
      const auto space = line.find(' ');
      const std::string key = line.substr(0, space), value = space == std::string::npos ? "" : line.substr(space + 1);
      int w = 0, h = 0;
      if (key == "method") method = value;
      else if (key == "set") sets.push_back(value);
      else if (key == "profile") profile = oitref::parseProfile(value);
      else if (key == "size") oitref::tools::parseSize(value, "--size", w, h);
      else if (key == "memory") (void)oitref::tools::parseByteSize(value, "--memory-limit");
    }
    std::unique_ptr<oitref::Method> m = oitref::makeMethod(method, oitref::tools::methodOptionsFrom(sets));
    const oitref::Scene& scene = tinyScene();
    static const oitref::SceneGeometry geometry = oitref::buildSceneGeometry(scene);
    static oitref::Renderer renderer(oitref::RendererOptions{1, 0});
    const oitref::FrameContext context{scene, geometry, scene.width, scene.height, profile, renderer, uint64_t(1) << 30};
    oitref::FrameResult frame;
    try {
      oitref::checkMemory(*m, scene.width, scene.height, geometry, uint64_t(1) << 30);
      frame = m->render(context);
    } catch (const std::runtime_error&) {
      // Refused, as it should be: options that ask for more than 1 GiB (checkMemory), or a frame
      // beyond a limit the options set (the A-buffer's max_fragments). A logic_error is a finding.
      return 0;
    }
    if (!m->info().nonFiniteWhen.empty()) return 0;
    for (int y = 0; y < frame.finalFloat.height(); ++y)
      for (int x = 0; x < frame.finalFloat.width(); ++x)
        for (int c = 0; c < 4; ++c)
          if (std::isnan(frame.finalFloat.fetch(x, y)[c])) __builtin_trap();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
