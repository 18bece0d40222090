// over's `faces` option (the bigwheels OIT demo's "split draw calls for back/front faces"): two
// full-screen layers, the nearer one facing the camera and submitted first, the farther one
// turned away; the expected colours are OVER in the order each option draws, in double.
#include <catch2/catch.hpp>

#include <map>
#include <string>

#include "method_fixture.h"
#include "methods/methods.h"

namespace oitref::test {
namespace {

glm::dvec3 overOnto(const glm::vec4& layer, const glm::dvec3& below) {
  return glm::dvec3(glm::vec3(layer)) * double(layer.a) + below * (1.0 - double(layer.a));
}

}  // namespace

TEST_CASE("over faces: back faces first, then front faces, as two culled draws", "[methods][over]") {
  const glm::vec3 background = {0.2f, 0.3f, 0.4f};
  const glm::vec4 front = {0.9f, 0.2f, 0.1f, 0.4f}, back = {0.1f, 0.3f, 0.9f, 0.5f};
  Scene s = layerScene(4, background);
  s.objects.push_back(quad({0.0f, 0.0f, 0.0f}, 50.0f, front));                 // counter-clockwise towards the camera
  s.objects.push_back(quad({0.0f, 0.0f, -1.0f}, 50.0f, back, {0, 180, 0}));    // farther, turned away: its back face
  const glm::dvec3 bg(background);
  const std::map<std::string, glm::dvec3> expected = {
      {"all", overOnto(back, overOnto(front, bg))},     // submission order: the far layer lands on top
      {"split", overOnto(front, overOnto(back, bg))},   // the back face first: here back to front
      {"back", overOnto(back, bg)},
      {"front", overOnto(front, bg)}};
  for (const auto& [faces, want] : expected) {
    INFO("faces=" << faces);
    const FrameResult f = render(s, "over", {{"faces", faces}});
    REQUIRE(f.passes.size() == 1 + methods::overDraws(faces).size());
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) requireClose(f.finalFloat, x, y, want, 1e-6, faces.c_str());
  }
  // The orders differ by far more than the bound, so a wrong order fails above.
  REQUIRE(glm::length(expected.at("all") - expected.at("split")) > 0.1);
}

}  // namespace oitref::test
