// The method kit (oitref/oit/method_kit.h) as a user outside the tree meets it: examples/custom_method's
// clamped_sum, written with the public headers alone and registered with registerMethod, must
// compute its closed form; the kit's declarations, handles and option conversions must refuse
// what cannot work.
#include <catch2/catch.hpp>

#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include "../examples/custom_method/clamped_sum.h"
#include "oitref/oit/frame.h"
#include "oitref/oit/method_kit.h"
#include "tools/stress.h"

namespace oitref::test {
namespace {

void registerExampleOnce() {
  static std::once_flag once;
  std::call_once(once, [] { custom::registerClampedSum(); });
}

// The centre pixel of the frame's RGBA32F composite.
glm::vec3 centre(const FrameResult& frame) {
  return glm::vec3(frame.finalFloat.fetch(frame.finalFloat.width() / 2, frame.finalFloat.height() / 2));
}

FrameResult renderAt8x8(const Scene& scene, const std::string& method, const OptionValues& options) {
  FrameRequest r;
  r.method = method;
  r.options = options;
  r.width = r.height = 8;
  r.threads = 1;
  return renderFrame(scene, r);
}

}  // namespace

TEST_CASE("method kit: the example's clamped_sum is Σc·α + C0·max(0, 1 − Σα), in double", "[methods][kit]") {
  registerExampleOnce();
  const tools::StressCondition base = tools::stressConditions().front();
  bool clampMattered = false;
  for (int layers : {1, 2, 5, 16})
    for (float alpha : {0.1f, 0.5f, 0.9f}) {
      INFO(layers << " layers of alpha " << alpha);
      const Scene scene = tools::stressScene(base, layers, alpha, 8, 8);
      // The closed form over the layers' colours and alphas, in double: order does not matter.
      glm::dvec3 sum(0.0);
      double alphas = 0;
      for (const SceneObject& o : scene.objects) {
        sum += glm::dvec3(glm::vec3(*o.colorOverride)) * double(o.colorOverride->a);
        alphas += double(o.colorOverride->a);
      }
      const glm::dvec3 expected = sum + glm::dvec3(scene.background) * std::max(0.0, 1.0 - alphas);
      const glm::vec3 got = centre(renderAt8x8(scene, "clamped_sum", {{"accum", "rgba32f"}}));
      for (int c = 0; c < 3; ++c) CHECK(std::fabs(double(got[c]) - expected[c]) <= 1e-6 * layers);
      // Where the alphas sum past 1 it is not the weighted sum, whose background weight goes negative.
      if (alphas > 1.0) {
        const glm::vec3 wsum = centre(renderAt8x8(scene, "wsum", {{"accum", "rgba32f"}}));
        CHECK(wsum != got);
        clampMattered = true;
      }
    }
  CHECK(clampMattered);
}

TEST_CASE("method kit: attachments are declared once, and a frame reaches only those", "[methods][kit]") {
  AttachmentList list;
  REQUIRE(list.declared().size() == 2);  // the opaque pass's two
  CHECK(list.declared()[AttachmentList::kOpaque.index].name == "opaque");
  CHECK(list.declared()[AttachmentList::kDepth.index].isDepth);
  const ColorHandle accum = list.color("accum", "rgba16f", "Σ");
  const DepthHandle second = list.depth("second_depth", DepthFormat::D32F, "a second depth");
  CHECK(accum.index == 2);
  CHECK(second.index == 3);
  CHECK_THROWS_WITH(list.color("accum", "rgba32f", "again"), Catch::Contains("'accum' is declared twice"));
  CHECK_THROWS_WITH(list.color("bad", "rgba17f", "no such format"), Catch::Contains("rgba17f"));

  const Scene scene = tools::stressScene(tools::stressConditions().front(), 1, 0.5f, 4, 4);
  const SceneGeometry geometry = buildSceneGeometry(scene);
  Renderer renderer(RendererOptions{1});
  const FrameContext context{scene, geometry, 4, 4, exactProfile(), renderer};
  FrameTargets targets(list.declared(), context);
  CHECK(targets[accum].format().name() == "rgba16f");
  CHECK(targets[second].format() == DepthFormat::D32F);
  CHECK(&targets[AttachmentList::kOpaque] == &targets.opaque());
  CHECK_THROWS_AS(targets[ColorHandle{}], std::logic_error);  // never declared
  CHECK_THROWS_AS(targets[ColorHandle{second.index}], std::logic_error);  // a depth buffer, not a colour image
  CHECK_THROWS_AS(targets[DepthHandle{accum.index}], std::logic_error);
  FrameResult result;
  targets.finish(result, accum);
  REQUIRE(result.dump.size() == 2);  // the colour attachments, in declaration order
  CHECK(result.dump[0].first == "opaque");
  CHECK(result.dump[1].first == "accum");
}

TEST_CASE("MethodOptions: integers, formats and choices converted in one place", "[methods][kit]") {
  const MethodInfo info{"kit_options",
                        "options of every kind",
                        {{"k", "4", "nodes", {}, OptionNumber::integer(1, 64)},
                         {"accum", "rgba16f", "format", {"rgba16f", "rgba:e5m2"}},
                         {"weight", "z5", "weight", {"one", "z3", "z5"}},
                         {"bias", "0.5", "bias", {}, OptionNumber::real(0, 1)}}};
  enum class Weight { One, Z3, Z5 };
  const MethodOptions defaults(info, {});
  CHECK(defaults.integer("k") == 4);
  CHECK(defaults.format("accum").name() == "rgba16f");
  CHECK(defaults.choice<Weight>("weight") == Weight::Z5);
  const MethodOptions given(info, {{"k", "64"}, {"accum", "rgba:e5m2"}, {"weight", "one"}});
  CHECK(given.integer("k") == 64);
  CHECK(given.format("accum").name() == parseFormat("rgba:e5m2").name());
  CHECK(given.choice<Weight>("weight") == Weight::One);
  CHECK_THROWS_WITH(defaults.integer("bias"), Catch::Contains("option 'bias'") && Catch::Contains("not an integer"));
  CHECK_THROWS_AS(defaults.choice<Weight>("k"), std::logic_error);  // k has no choices
  CHECK(defaults.is("weight", "z5"));
  CHECK_FALSE(given.is("weight", "z5"));
  CHECK_THROWS_WITH(defaults.is("weight", "z4"), Catch::Contains("no choice 'z4'"));  // a misspelt comparison
  CHECK_THROWS_WITH(MethodOptions(info, {{"k", "65"}}), Catch::Contains("outside 1..64"));
}

}  // namespace oitref::test
