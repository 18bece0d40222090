// The method registry (oitref/oit/method.h): a method registered from outside the built-in list is
// made, listed, studied and stressed like a built-in one, and a description that could not work
// is refused at registration, naming the method and the field.
#include <catch2/catch.hpp>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "oitref/oit/frame.h"
#include "oitref/oit/method.h"
#include "tools/stress.h"
#include "tools/study.h"

namespace oitref::test {
namespace {

// The opaque method's own description under another name, made by the built-in factory: its
// frames must be the opaque method's, bit for bit.
MethodInfo renamedOpaque(const std::string& name) {
  MethodInfo info = allMethods().front();
  REQUIRE(info.name == "opaque");
  info.name = name;
  return info;
}

MethodInfo withOption(const std::string& name, MethodOption option) {
  MethodInfo info = renamedOpaque(name);
  info.options.push_back(std::move(option));
  return info;
}

void refuses(MethodInfo info, const std::string& expected) {
  INFO(info.name);
  REQUIRE_THROWS_WITH(registerMethod(info, [](const MethodOptions&) { return makeMethod("opaque"); }),
                      Catch::Contains("method '" + info.name + "'") && Catch::Contains(expected));
  const std::vector<MethodInfo> all = allMethods();
  CHECK(std::none_of(all.begin(), all.end(), [&](const MethodInfo& m) { return m.name == info.name; }));
}

}  // namespace

TEST_CASE("registerMethod: an added method is made, listed, studied and stressed", "[methods][registry]") {
  const size_t builtIn = allMethods().size();
  MethodInfo info = renamedOpaque("opaque_again");
  info.studyVariants = {{}};
  info.stressVariants = {{}};
  registerMethod(info, [](const MethodOptions&) { return makeMethod("opaque"); });
  const std::vector<MethodInfo> all = allMethods();
  REQUIRE(all.size() == builtIn + 1);
  CHECK(all.back().name == "opaque_again");  // after the built-in ones, in the order added

  FrameRequest request;
  request.width = 64, request.height = 48;
  const Scene scene = loadScene(OITREF_SOURCE_DIR "/scenes/glass.json");
  request.method = "opaque";
  const std::string opaque = frameHash(renderFrame(scene, request));
  request.method = "opaque_again";
  CHECK(frameHash(renderFrame(scene, request)) == opaque);

  const auto studied = tools::studyVariants();
  CHECK(std::count_if(studied.begin(), studied.end(), [](const tools::StudyVariant& v) { return v.method == "opaque_again"; }) == 2);
  const auto stressed = tools::stressConfigs();
  CHECK(std::count_if(stressed.begin(), stressed.end(), [](const tools::StressConfig& c) { return c.method == "opaque_again"; }) == 1);

  // The name is now taken, by it and by every built-in method.
  CHECK_THROWS_WITH(registerMethod(renamedOpaque("opaque_again"), [](const MethodOptions&) { return makeMethod("opaque"); }),
                    Catch::Contains("method 'opaque_again' is already registered"));
  for (const MethodInfo& m : all) CHECK_THROWS_AS(registerMethod(m, [](const MethodOptions&) { return makeMethod("opaque"); }), std::invalid_argument);
}

TEST_CASE("registerMethod: a description that could not work is refused", "[methods][registry][bad_input]") {
  refuses(renamedOpaque("Opaque"), "lower-case letter");
  refuses(renamedOpaque(""), "lower-case letter");
  refuses(renamedOpaque("two words"), "lower-case letter");
  MethodOption format{"accum", "rgba16f", "accumulation format", {"rgba16f", "rgba32f"}};
  MethodInfo twice = withOption("dup_option", format);
  twice.options.push_back(format);
  refuses(twice, "option 'accum' is declared twice");
  refuses(withOption("bad_default", {"accum", "rgba8", "accumulation format", {"rgba16f", "rgba32f"}}),
          "the default 'rgba8' is not one of its choices");
  refuses(withOption("bad_number", {"k", "0", "nodes", {}, OptionNumber::integer(1, 16)}), "the default of method 'bad_number' option 'k': '0' is outside 1..16");
  MethodInfo preset = withOption("bad_preset", format);
  preset.presets = {{"paper", "as printed", {{"acum", "rgba32f"}}}};
  refuses(preset, "preset 'paper' sets option 'acum'");
  MethodInfo variant = withOption("bad_variant", format);
  variant.studyVariants = {{{"accum", "rgba8"}}};
  refuses(variant, "study variant");
  MethodInfo stress = withOption("bad_stress", format);
  stress.stressVariants = {{{"samples", "4"}}};
  refuses(stress, "stress variant");
  CHECK_THROWS_WITH(registerMethod(renamedOpaque("no_factory"), nullptr), Catch::Contains("no factory"));
}

}  // namespace oitref::test
