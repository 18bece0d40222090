// Bad input gets a clear error naming the file and the field (or line), never a crash or a
// silently wrong image. Scene-format details beyond these are in test_scene.cpp; the
// command-line errors (sizes, memory limits, the A-buffer budget) are ctest cases in
// tests/CMakeLists.txt, label bad_input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "oitref/oit/frame.h"
#include "oitref/oit/method.h"
#include "oitref/oit/metrics.h"
#include "oitref/oit/scene_geometry.h"
#include "temp_files.h"

using namespace oitref;
namespace fs = std::filesystem;

namespace {

fs::path testDir() { return test::tempFolder("oitref-bad-input-test"); }
std::string write(const std::string& name, const std::string& bytes) { return test::writeFile(testDir(), name, bytes); }

template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

std::string sceneError(const std::string& json) {
  return errorOf([&] { parseScene(json, "s.json"); });
}

std::string meshError(const std::string& name, const std::string& bytes) {
  const std::string path = write(name, bytes);
  return errorOf([&] { loadMesh(path); });
}

std::string binaryPlyTriangle(const float (&xyz)[9], const int (&indices)[3]) {
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  ply.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  ply += char(3);
  ply.append(reinterpret_cast<const char*>(indices), sizeof indices);
  return ply;
}

}  // namespace

TEST_CASE("bad input: malformed and truncated JSON name the file and the position", "[bad_input]") {
  CHECK_THAT(sceneError(R"({"objects": [{"type": "mesh")"), Catch::StartsWith("s.json: malformed JSON") &&
                                                             Catch::Contains("unexpected end of input"));
  CHECK_THAT(sceneError(""), Catch::StartsWith("s.json: malformed JSON"));
  CHECK_THAT(sceneError(R"({"objects": [], "back": [0, 0, 0],})"), Catch::StartsWith("s.json: malformed JSON") &&
                                                                    Catch::Contains("line 1"));
  CHECK_THAT(sceneError("[1, 2]"), Catch::Contains("s.json: expected a JSON object at the top level"));
  // Found by fuzz_scene_json: a number beyond double's range was an uncaught json out_of_range.
  CHECK_THAT(sceneError(R"({"objects": [], "back": [1e999, 0, 0]})"), Catch::StartsWith("s.json: malformed JSON") &&
                                                                      Catch::Contains("number overflow"));
}

TEST_CASE("bad input: wrong types name the field and what was expected", "[bad_input]") {
  CHECK_THAT(sceneError(R"({"objects": {}})"), Catch::Contains("s.json: objects: expected an array of objects"));
  CHECK_THAT(sceneError(R"({"objects": [], "camera": []})"), Catch::Contains("camera: expected an object"));
  CHECK_THAT(sceneError(R"({"objects": [], "back": [1, 2]})"), Catch::Contains("back: expected an array of 3 numbers"));
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"near": "0.1"}})"),
             Catch::Contains("camera.near: expected a number, got string"));
  CHECK_THAT(sceneError(R"({"objects": [{"type": "mesh", "file_path": "a.obj", "scale": "big"}]})"),
             Catch::Contains("objects[0].scale: expected a number, got string"));
  CHECK_THAT(sceneError(R"({"objects": [{"type": "mesh", "file_path": "a.obj", "transparent": 1}]})"),
             Catch::Contains("objects[0].transparent: expected true or false"));
  CHECK_THAT(sceneError(R"({"objects": [{"type": "mesh", "file_path": 3}]})"),
             Catch::Contains("objects[0].file_path: expected a path string"));
  CHECK_THAT(sceneError(R"({"objects": [{"type": "particle", "count": 2.5}]})"),
             Catch::Contains("objects[0].count: expected an integer, got number"));
  CHECK_THAT(sceneError(R"({"objects": [], "resolution": [-4, 10]})"),
             Catch::Contains("resolution[0]: expected an integer in [1, 16384], got -4"));
  CHECK_THAT(sceneError(R"({"objects": [], "resolution": [640, 1e9]})"), Catch::Contains("resolution[1]"));
}

TEST_CASE("bad input: unknown keys suggest the nearest valid one", "[bad_input]") {
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"fovy": 60}})"),
             Catch::Contains("camera.fovy: unknown key (did you mean 'fov_y'?)"));
  CHECK_THAT(sceneError(R"({"objets": []})"), Catch::Contains("objets: unknown key (did you mean 'objects'?)"));
}

TEST_CASE("bad input: every camera rule", "[bad_input]") {
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"near": -1}})"), Catch::Contains("camera.near: must be positive"));
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"near": 0.5, "far": 0.5}})"),
             Catch::Contains("camera.far: must be greater than near"));
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"fov_y": 0}})"), Catch::Contains("camera.fov_y: must lie in (0, 180)"));
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"fov_y": -30}})"), Catch::Contains("camera.fov_y"));
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"position": [1, 2, 3], "target": [1, 2, 3]}})"),
             Catch::Contains("camera.target: must differ from the position"));
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"position": [0, 0, 5], "up": [0, 0, 2]}})"),
             Catch::Contains("camera.up: must not be parallel to the view direction"));
}

TEST_CASE("bad input: meshes with non-finite coordinates or bad indices, missing or unreadable files", "[bad_input]") {
  CHECK_THAT(meshError("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
             Catch::Contains("nan.obj': vertex 0 of mesh 0 has a non-finite coordinate"));
  CHECK_THAT(meshError("inf.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n"),
             Catch::Contains("vertex 1 of mesh 0 has a non-finite coordinate"));
  CHECK_THAT(meshError("nan.ply", binaryPlyTriangle({0, 0, 0, 1, 0, 0, 0, NAN, 0}, {0, 1, 2})),
             Catch::Contains("nan.ply': vertex 2 of mesh 0 has a non-finite coordinate"));
  CHECK_THAT(meshError("range.ply", binaryPlyTriangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 7})),
             Catch::Contains("range.ply': face 0 has an index out of range"));
  CHECK_THAT(meshError("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
             Catch::Contains("cannot load mesh") && Catch::Contains("index out of range"));
  CHECK_THAT(meshError("garbage.obj", "this is not a mesh\n"), Catch::Contains("garbage.obj' has no triangles"));
  CHECK_THAT(meshError("empty.obj", ""), Catch::Contains("cannot load mesh") && Catch::Contains("empty.obj"));
  CHECK_THAT(errorOf([] { loadMesh((testDir() / "missing.obj").string()); }), Catch::Contains("missing.obj' does not exist"));
  CHECK_THAT(errorOf([] { loadMesh(testDir().string()); }), Catch::Contains("is not a regular file"));
  // Found by fuzz_mesh: files on which Debian 12's Assimp aborts or hangs are errors too.
  const std::string offCrash =
      std::string("OFF\n4 2 00\n1 1 0\x0f") + "0 " + std::string(18, '\0') + "1 0\n3 0 1 2\n3 0 2 3\n";
  CHECK_THAT(meshError("assert.off", offCrash), Catch::Contains("assert.off': the importer (Assimp) crashed on this file"));
  CHECK_THAT(meshError("header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"),
             Catch::Contains("header.ply': PLY header has no end_header line"));
  // In a scene, the error also names the scene file and the object.
  write("tri_nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string scene = write("nan_scene.json", R"({"objects": [{"type": "mesh", "file_path": "tri_nan.obj"}]})");
  CHECK_THAT(errorOf([&] { loadScene(scene); }),
             Catch::Contains("nan_scene.json: objects[0].file_path: mesh '") && Catch::Contains("non-finite coordinate"));
}

TEST_CASE("bad input: degenerate and zero-area triangles are drawn as GL draws them: not at all", "[bad_input]") {
  // A square, once alone and once with a zero-area sliver and a repeated-vertex triangle in
  // between: the images must be identical bits.
  write("clean.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n");
  write("degenerate.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 -1 0\nf 1 2 3\nf 1 5 2\nf 3 3 4\nf 1 3 4\n");
  auto render = [](const std::string& mesh) {
    const std::string path = write(mesh + ".json", R"({"resolution": [32, 32], "objects": [{"type": "mesh", "file_path": ")" +
                                                       mesh + R"(.obj", "color_override": [0.8, 0.4, 0.2, 0.5]}]})");
    const Scene scene = loadScene(path);
    Renderer r(RendererOptions{2, 16});
    return SceneFrames(scene, r).render(*makeMethod("over"));
  };
  const FrameResult clean = render("clean"), degenerate = render("degenerate");
  CHECK(clean.final8.sameBits(degenerate.final8));
  CHECK(clean.finalFloat.sameBits(degenerate.finalFloat));
  CHECK(clean.fragmentsShaded() == degenerate.fragmentsShaded());
}

TEST_CASE("bad input: unknown methods and options suggest the nearest name", "[bad_input]") {
  CHECK_THAT(errorOf([] { makeMethod("abufer"); }),
             Catch::Contains("unknown method 'abufer' (did you mean 'abuffer'?)") && Catch::Contains("valid:"));
  CHECK_THAT(errorOf([] { makeMethod("wboit", {{"wieght", "mb7"}}); }),
             Catch::Contains("method 'wboit' has no option 'wieght'") && Catch::Contains("did you mean 'weight'?"));
  CHECK_THAT(errorOf([] { makeMethod("wboit", {{"weight", "mb11"}}); }),
             Catch::Contains("option 'weight': 'mb11' is not one of"));
  CHECK_THAT(errorOf([] { makeMethod("peel", {{"passes", "many"}}); }),
             Catch::Contains("option 'passes': 'many' is not a finite number (an integer in 1..1024)"));
  CHECK_THAT(errorOf([] { makeMethod("peel", {{"passes", "0"}}); }), Catch::Contains("option 'passes': '0' is outside 1..1024"));
  CHECK_THAT(errorOf([] { makeMethod("wboit", {{"preset", "thesys"}}); }),
             Catch::Contains("option 'preset': 'thesys' is not one of none, thesis"));
  CHECK_THAT(errorOf([] { makeMethod("over", {{"preset", "thesis"}}); }), Catch::Contains("method 'over' has no option 'preset'"));
}

// A preset's values replace the defaults, and the options given beside it replace those; every
// preset of every method names only options the method declares, with values among their choices.
TEST_CASE("methods: presets set options, and options given beside a preset win", "[methods]") {
  const auto findMethod = [](const std::string& name) {
    for (const MethodInfo& m : allMethods())
      if (m.name == name) return m;
    FAIL("no method " << name);
    return MethodInfo{};
  };
  const MethodOptions plain(findMethod("wboit"), {});
  CHECK(plain.text("preset") == "none");
  CHECK(plain.text("clamp") == "mb");
  const MethodOptions thesis(findMethod("wboit"), {{"preset", "thesis"}});
  CHECK(thesis.text("clamp") == "none");
  CHECK(thesis.text("accum") == "rgba32f");
  const MethodOptions sixteen(findMethod("wboit"), {{"preset", "thesis"}, {"accum", "rgba16f"}});
  CHECK(sixteen.text("accum") == "rgba16f");
  CHECK(sixteen.text("clamp") == "none");
  int presets = 0;
  for (const MethodInfo& m : allMethods())
    for (const MethodPreset& p : m.presets) {
      const MethodOptions o(m, {{"preset", p.name}});
      for (const auto& entry : p.values) {
        const std::string &key = entry.first, &value = entry.second;
        const auto declared = std::find_if(m.options.begin(), m.options.end(), [&](const MethodOption& d) { return d.key == key; });
        REQUIRE(declared != m.options.end());
        CHECK((declared->choices.empty() || std::count(declared->choices.begin(), declared->choices.end(), value) == 1));
        CHECK(o.text(key) == value);
      }
      ++presets;
    }
  CHECK(presets >= 4);
}

TEST_CASE("bad input: memory needs are checked before allocating", "[bad_input]") {
  const Scene scene = parseScene(R"({"objects": []})", "empty.json");
  const SceneGeometry g = buildSceneGeometry(scene);
  const auto wboit = makeMethod("wboit");
  // wboit: opaque 4 + depth 4 + rgba32f 16 + r32f 4 = 28 B/pixel, + 16 analysis + 4 presented.
  uint64_t total = 0;
  for (const MemoryItem& i : wboit->memoryNeed(1000, 1000, g)) total += i.bytes;
  CHECK(total == 48'000'000);
  CHECK_NOTHROW(checkMemory(*wboit, 1000, 1000, g, 48'000'000));
  CHECK_THAT(errorOf([&] { checkMemory(*wboit, 1000, 1000, g, 47'999'999); }),
             Catch::Contains("method 'wboit' at 1000x1000 needs 45.8 MiB, above the memory limit of 45.8 MiB") &&
                 Catch::Contains("attachments (28 B/pixel)"));
  CHECK_THAT(errorOf([&] { checkMemory(*makeMethod("raycast"), 16384, 16384, g, uint64_t(1) << 30); }),
             Catch::Contains("needs 5.0 GiB"));
}

// Issue 18, class 4: every number option states its kind and range (OptionNumber), and
// MethodOptions checks every given value against it, in one place.
TEST_CASE("bad input: number options refuse NaN, infinities, fractions and values out of range", "[bad_input]") {
  const struct {
    const char* method;
    const char* key;
    const char* value;
    const char* message;
  } cases[] = {
      {"mboit", "bias", "nan", "option 'bias': 'nan' is not a finite number (a number in 0..1 or auto)"},
      {"mboit", "bias", "-1", "option 'bias': '-1' is outside 0..1 or auto"},
      {"mboit", "overestimation", "nan", "option 'overestimation': 'nan' is not a finite number (a number in 0..1)"},
      {"mboit", "overestimation", "1.5", "option 'overestimation': '1.5' is outside 0..1"},
      {"mt", "bias", "inf", "option 'bias': 'inf' is not a finite number (a number in 0..1)"},
      {"mt", "bias", "-1", "option 'bias': '-1' is outside 0..1"},
      {"peel", "passes", "nan", "option 'passes': 'nan' is not a finite number (an integer in 1..1024)"},
      {"peel", "passes", "2.5", "option 'passes': '2.5' is not an integer (an integer in 1..1024)"},
      {"dualpeel", "passes", "-3", "option 'passes': '-3' is outside 1..1024"},
      {"dualpeel", "passes", "1e9", "option 'passes': '1e9' is outside 1..1024"},
      {"stochastic", "seed", "-1", "option 'seed': '-1' is outside 0..4294967295"},
      {"stochastic", "seed", "0.5", "option 'seed': '0.5' is not an integer"},
      {"abuffer", "max_fragments", "1e30", "option 'max_fragments': '1e30' is outside 1..1099511627776"},
      {"abuffer", "max_fragments", "", "option 'max_fragments': '' is not a finite number"},
  };
  for (const auto& c : cases) {
    INFO(c.method << " " << c.key << "=" << c.value);
    CHECK_THAT(errorOf([&] { makeMethod(c.method, {{c.key, c.value}}); }),
               Catch::Contains(std::string("method '") + c.method + "' " + c.message));
  }
  // In range, they are taken: the ends, "auto" where it is allowed, an integer written as a real.
  CHECK_NOTHROW(makeMethod("mboit", {{"bias", "auto"}}));
  CHECK_NOTHROW(makeMethod("mboit", {{"bias", "0"}, {"overestimation", "1"}}));
  CHECK_NOTHROW(makeMethod("peel", {{"passes", "1024"}}));
  CHECK_NOTHROW(makeMethod("dualpeel", {{"passes", "4.0"}}));
  CHECK_NOTHROW(makeMethod("stochastic", {{"seed", "4294967295"}}));
  CHECK_THAT(errorOf([] { makeMethod("mt", {{"bias", "auto"}}); }), Catch::Contains("'auto' is not a finite number"));
}

// Issue 18, class 1: a scene number that does not fit the fp32 it becomes is refused, naming the
// field — every numeric field goes through Reader::number.
TEST_CASE("bad input: scene numbers beyond fp32 are refused, naming the field", "[bad_input]") {
  const std::string quad = R"("type": "mesh", "file_path": "meshes/quad.obj")";
  const struct {
    std::string json, message;
  } cases[] = {
      {R"({"objects": [{)" + quad + R"(, "scale": 1e39}]})", "s.json: objects[0].scale: 1e+39 does not fit in fp32 (largest 3.40282347e38)"},
      {R"({"objects": [{)" + quad + R"(, "position": [0, -1e39, 0]}]})", "s.json: objects[0].position[1]: -1e+39 does not fit in fp32"},
      {R"({"objects": [{)" + quad + R"(, "rotation": [1e39, 0, 0]}]})", "s.json: objects[0].rotation[0]: 1e+39 does not fit in fp32"},
      {R"({"objects": [{)" + quad + R"(, "color_override": [1e39, 0, 0, 1]}]})", "objects[0].color_override[0]: 1e+39 does not fit in fp32"},
      {R"({"objects": [{)" + quad + R"(, "scale": 1e-50}]})", "s.json: objects[0].scale: 1e-50 does not fit in fp32 (it would be 0)"},
      {R"({"objects": [{"type": "particle", "count": 2, "size": 1e39}]})", "s.json: objects[0].size: 1e+39 does not fit in fp32"},
      {R"({"objects": [], "back": [0, 1e39, 0]})", "s.json: back[1]: 1e+39 does not fit in fp32"},
      {R"({"objects": [], "camera": {"position": [1e39, 0, 0]}})", "s.json: camera.position[0]: 1e+39 does not fit in fp32"},
      {R"({"objects": [], "camera": {"far": 1e39}})", "s.json: camera.far: 1e+39 does not fit in fp32"},
  };
  for (const auto& c : cases) {
    INFO(c.json);
    CHECK_THAT(sceneError(c.json), Catch::Contains(c.message));
  }
  // The largest fp32 and denormals still fit.
  CHECK_THAT(sceneError(R"({"objects": [], "back": [3.4e38, 1e-40, 0]})"), Catch::Equals("no error"));
}

// Issue 18, class 3: a mesh's vertex colours obey color_override's rule (scene/colour_rule.h),
// refused with the file, the vertex and the channel.
TEST_CASE("bad input: mesh vertex colours: NaN, negative, alpha above 1", "[bad_input]") {
  auto ply = [](const std::string& secondVertexColour) {
    return "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "property float red\nproperty float green\nproperty float blue\nproperty float alpha\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 0 1\n1 0 0 " +
           secondVertexColour + "\n0 1 0 0 0 1 1\n3 0 1 2\n";
  };
  CHECK_THAT(meshError("colour_nan.ply", ply("nan 0.5 0 1")),
             Catch::Contains("colour_nan.ply': vertex 1 of mesh 0, colour channel r (nan): colour components must be finite"));
  CHECK_THAT(meshError("colour_negative.ply", ply("0.5 -0.5 0 1")),
             Catch::Contains("colour_negative.ply': vertex 1 of mesh 0, colour channel g (-0.500000): colour components must not be negative"));
  CHECK_THAT(meshError("colour_alpha.ply", ply("0.5 0.5 0 2")),
             Catch::Contains("colour_alpha.ply': vertex 1 of mesh 0, colour channel a (2.000000): alpha must lie in [0, 1]"));
  CHECK_THAT(meshError("colour_negative.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 -2 0\nv 0 1 0 0 0 1\nf 1 2 3\n"),
             Catch::Contains("colour_negative.obj': vertex 1 of mesh 0, colour channel g (-2.000000): colour components must not be negative"));
  // An HDR colour (RGB above 1) is a colour: taken, as in color_override.
  CHECK_THAT(meshError("colour_hdr.ply", ply("4 0.5 0 1")), Catch::Equals("no error"));
  CHECK_THAT(sceneError(R"({"objects": [{"type": "mesh", "file_path": "q.obj", "color_override": [4, 0, 0, 1]}]})"),
             !Catch::Contains("colour"));
}

// Issue 18, class 2: a camera whose fp32 projection overflows, or cannot be undone into finite
// rays, is refused when the scene is read — by the check both ground truths share
// (Camera::projectionProblem, which Camera::projection also throws), so the rasterizer no longer
// draws a blank frame where the ray cast refuses.
TEST_CASE("bad input: cameras whose fp32 projection shows nothing are refused by one check", "[bad_input]") {
  auto scene = [](const std::string& camera) {
    return R"({"objects": [], "camera": {"position": [0, 0, 3], "target": [0, 0, 0], )" + camera + "}}";
  };
  CHECK_THAT(sceneError(scene(R"("near": 0.1, "far": 3e38)")),
             Catch::Contains("s.json: camera: the perspective projection of fov_y 60, near 0.1, far 3e+38 is not finite in fp32 "
                             "(2·far·near overflows)"));
  CHECK_THAT(sceneError(scene(R"("fov_y": 1e-40)")), Catch::Contains("is not finite in fp32 (1/tan(fov_y/2) overflows)"));
  CHECK_THAT(sceneError(scene(R"("near": 1e-30, "far": 1e30)")),
             Catch::Contains("s.json: camera: near 1e-30 and far 1e+30 are too far apart for fp32: the projection puts every "
                             "depth on the far plane"));
  // Found by fuzz_camera: a denormal depth term (the rasterizer drew nothing, the ray cast NaN).
  CHECK_THAT(sceneError(scene(R"("near": 7e-41, "far": 50)")),
             Catch::Contains("s.json: camera: near 7.00005e-41 is so small that the perspective projection's depth term "
                             "2·far·near/(far − near) is denormal in fp32"));
  // Found by fuzz_camera: a camera beyond Embree's coordinate range aborted the process inside it.
  CHECK_THAT(sceneError(R"({"objects": [], "camera": {"position": [-1.2e19, 0, 0], "target": [0, 0, 0]}})"),
             Catch::Contains("s.json: camera: position -1.2e+19 lies beyond ±1.844e18, where the ray cast (Embree) cannot trace from"));
  // Extreme but workable cameras are taken, and the projection throws what the reader says.
  CHECK_THAT(sceneError(scene(R"("near": 0.1, "far": 1e37)")), Catch::Equals("no error"));
  CHECK_THAT(sceneError(scene(R"("near": 1e-6, "far": 1e6)")), Catch::Equals("no error"));
  Camera c;
  c.fovYDegrees = 1e-40f;
  CHECK_THAT(errorOf([&] { (void)c.projection(1.0f); }), Catch::Contains("camera: the perspective projection of fov_y"));
}

TEST_CASE("bad input: mesh headers that declare more than the file holds or the memory limit allows", "[bad_input]") {
  // 400 M vertices declared in a few hundred bytes: Assimp took 4.7 GB (binary PLY), 9.4 GB (OFF)
  // or more than 100 s (ASCII PLY) before failing; now the header's counts refuse them at once.
  const std::string plyHeader = "element vertex 400000000\nproperty float x\nproperty float y\nproperty float z\n"
                                "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  // Binary: 400 M × 12 bytes of vertices and one face of at least its 1-byte count.
  CHECK_THAT(meshError("huge.ply", "ply\nformat binary_little_endian 1.0\n" + plyHeader + std::string(100, '\0')),
             Catch::Contains("huge.ply': its header declares 400000000 × element 'vertex', 1 × element 'face', at least "
                             "4800000001 bytes of data, but the file holds 100 bytes after its header"));
  // ASCII: each of the 4 values of an item at least a character and a separator.
  CHECK_THAT(meshError("huge_ascii.ply", "ply\r\nformat ascii 1.0\r\n" + plyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
             Catch::Contains("at least 2400000002 bytes of data, but the file holds 26 bytes after its header"));
  CHECK_THAT(meshError("huge.off", "OFF\n400000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
             Catch::Contains("huge.off': its header declares 400000000 vertices and 1 faces, at least 2400000002 bytes of "
                             "data, but the file holds 26 bytes after its header"));
  CHECK_THAT(meshError("comment.off", "COFF # counts follow\n\n400000000 2 0\n0 0 0\n"),
             Catch::Contains("at least 2400000004 bytes of data, but the file holds 6 bytes after its header"));
  // A file that holds what it declares, but whose arrays would exceed the memory limit:
  // 3 vertices × 28 B + 1 face × 12 B = 96 B.
  const std::string tri = binaryPlyTriangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
  const std::string path = write("tri.ply", tri);
  CHECK_THAT(errorOf([&] { loadMesh(path, 120.0, 95); }),
             Catch::Contains("tri.ply': its header declares 3 vertices and 1 faces, at least 96 B once loaded (28 bytes a "
                             "vertex, 12 a face), above the memory limit of 95 B (--memory-limit)"));
  CHECK(loadMesh(path, 120.0, 96).indices.size() == 3);
  // Files that hold what they declare load as before (the built-in bunny, ASCII and binary PLY).
  CHECK(loadMesh(OITREF_SOURCE_DIR "/scenes/meshes/bunny.ply").positions.size() > 0);
  CHECK(loadMesh(write("ok.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")).indices.size() == 3);
  // In a scene, the limit is the command's --memory-limit (loadScene's).
  write("tri_scene.ply", tri);
  const std::string scene = write("tri_scene.json", R"({"objects": [{"type": "mesh", "file_path": "tri_scene.ply"}]})");
  CHECK_THAT(errorOf([&] { loadScene(scene, 95); }),
             Catch::Contains("tri_scene.json: objects[0].file_path: mesh '") && Catch::Contains("above the memory limit of 95 B"));
}

TEST_CASE("bad input: a near plane too close for its far plane is refused where the rasterizer would lose geometry",
          "[bad_input]") {
  // The oracle is the two ground truths themselves: the camera set in code (loadScene would
  // refuse it), the A-buffer's covered pixels against the ray cast's. depthPrecisionProblem must
  // speak exactly where the rasterizer loses pixels that the ray cast sees.
  const std::string quad = OITREF_SOURCE_DIR "/scenes/meshes/quad.obj";
  struct Case {
    float nearPlane, farPlane, distance;
    bool refused;
  };
  for (const Case c : {Case{1e-6f, 1e6f, 100.0f, true}, Case{1e-6f, 1e3f, 100.0f, true}, Case{1e-6f, 1e6f, 1e5f, true},
                       Case{1e-6f, 1e3f, 0.01f, false}, Case{1e-2f, 1e4f, 5.0f, false}, Case{1e-6f, 1e6f, 3.0f, false}}) {
    INFO("near " << c.nearPlane << ", far " << c.farPlane << ", quad at distance " << c.distance);
    const std::string json = R"({"resolution": [32, 24], "back": [0.1, 0.1, 0.1], "objects": [
        {"type": "mesh", "file_path": ")" + quad + R"(", "color_override": [0.9, 0.3, 0.1, 0.5], "rotation": [0, 0, 20],
         "scale": )" + std::to_string(0.8 * c.distance) + "}]}";
    Scene scene = loadScene(write("depth_precision.json", json));
    scene.camera.position = {0.0f, 0.0f, c.distance};
    scene.camera.nearPlane = c.nearPlane, scene.camera.farPlane = c.farPlane;
    const SceneGeometry geometry = buildSceneGeometry(scene);
    CHECK(depthPrecisionProblem(geometry).empty() == !c.refused);
    Renderer renderer(RendererOptions{2, 0});
    const FrameContext context{scene, geometry, 32, 24, exactProfile(), renderer};
    const FrameResult rays = makeMethod("raycast")->render(context), raster = makeMethod("abuffer")->render(context);
    int lost = 0, seen = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 32; ++x) {
        const bool rayCovered = rays.finalFloat.fetch(x, y).r != 0.1f, rasterCovered = raster.finalFloat.fetch(x, y).r != 0.1f;
        seen += rayCovered;
        lost += rayCovered && !rasterCovered;
      }
    CHECK(seen > 200);
    if (c.refused) CHECK(lost > 0);
    else CHECK(lost <= 12);  // pixels on an edge may fall on either side in the two
  }
  // The scene file names the camera's problem.
  const std::string json = R"({"camera": {"position": [0, 0, 100], "target": [0, 0, 0], "near": 1e-6, "far": 1e3},
      "objects": [{"type": "mesh", "file_path": ")" + quad + R"(", "scale": 30}]})";
  CHECK_THAT(errorOf([&] { loadScene(write("near_too_close.json", json)); }),
             Catch::Contains("near_too_close.json: camera: near 1e-06 and far 1000 leave fp32 depth no precision where "
                             "objects[0] lies: at view distance 100"));
}

TEST_CASE("bad input: extreme but valid cameras render what the ray cast sees", "[bad_input]") {
  // Inputs with a meaningful answer are rendered, not refused: the rasterizer's A-buffer against
  // the Embree ray cast (an independent ground truth), and the frame must not be blank.
  const std::string quad = OITREF_SOURCE_DIR "/scenes/meshes/quad.obj";
  for (const std::string camera : {R"("position": [0, 0, 3], "target": [0, 0, 0], "near": 0.1, "far": 1e37)",
                                   R"("position": [0, 0, 3], "target": [0, 0, 0], "near": 1e-6, "far": 1e6)",
                                   R"("position": [0.2, 0.1, 3], "target": [0.2, 0.1, 0], "fov_y": 1e-3)",
                                   R"("position": [0.2, 0.1, 3], "target": [0.2, 0.1, 0], "fov_y": 1e-6)",
                                   R"("position": [0, 0, 1e-4], "target": [0, 0, 0], "near": 1e-7, "far": 1)",
                                   R"("position": [0.2, 0.1, 3], "target": [0.2, 0.1, 0], "fov_y": 1e-30)"}) {
    INFO(camera);
    const std::string json = R"({"resolution": [32, 24], "back": [0.1, 0.1, 0.1], "camera": {)" + camera + R"(}, "objects": [
        {"type": "mesh", "file_path": ")" + quad + R"(", "color_override": [0.9, 0.3, 0.1, 0.5], "rotation": [0, 0, 20]},
        {"type": "mesh", "file_path": ")" + quad + R"(", "color_override": [0.1, 0.4, 0.9, 0.5], "position": [0.3, 0, -0.5]}]})";
    const Scene scene = loadScene(write("extreme.json", json));
    const SceneGeometry geometry = buildSceneGeometry(scene);
    Renderer renderer(RendererOptions{2, 0});
    const FrameContext context{scene, geometry, 32, 24, exactProfile(), renderer};
    const FrameResult rays = makeMethod("raycast")->render(context);
    if (camera.find("1e-30") != std::string::npos) {
      // Zoomed so far that the quads' fp32 clip coordinates (~1e32, the viewport spanning 384)
      // cannot be clipped to within a pixel: the ray cast sees both quads everywhere, the
      // rasterizer would have drawn a quarter of them; it refuses instead.
      CHECK_THROWS_AS(makeMethod("abuffer")->render(context), RasterPrecisionError);
      continue;
    }
    const FrameResult raster = makeMethod("abuffer")->render(context);
    const ImageDifference d = compareImages(raster.finalFloat, rays.finalFloat, 1.0 / 255);
    CHECK(d.nonFinitePixels == 0);
    CHECK(d.shareWithin() >= 0.95);  // pixels on an edge may fall on either side in the two
    int covered = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 32; ++x) covered += raster.finalFloat.fetch(x, y).r != 0.1f;
    CHECK(covered > 0);
  }
}
