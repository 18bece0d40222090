// Scenes: the JSON format and its errors, transforms, meshes through Assimp (files written by
// the test), particles and the shared shading function.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>

#include <glm/geometric.hpp>
#include <fstream>

#include "oitref/oit/scene_geometry.h"
#include "temp_files.h"

using namespace oitref;
namespace fs = std::filesystem;

namespace {

fs::path testDir() { return test::tempFolder("oitref-scene-test"); }
std::string write(const std::string& name, const std::string& text) { return test::writeFile(testDir(), name, text); }

std::string errorOf(const std::string& json) {
  try {
    parseScene(json, "s.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    out += t[(v >> 18) & 63];
    out += t[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? t[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? t[v & 63] : '=';
  }
  return out;
}

}  // namespace

TEST_CASE("scene: the thesis format parses, with camera, resolution and defaults", "[scene]") {
  const Scene s = parseScene(R"({
    "back": [0.1, 0.2, 0.3],
    "resolution": [320, 200],
    "camera": {"position": [0, 1, 5], "target": [0, 0, 0], "fov_y": 45, "near": 0.5, "far": 50},
    "objects": [
      {"type": "mesh", "file_path": "meshes/quad.obj", "color_override": [1, 0, 0, 0.5],
       "position": [1, 2, 3], "rotation": [0, -0.0, 90], "scale": 2},
      // the thesis's files carry comments like this one
      {"type": "particle", "count": 16, "position": [0, 0, 0], "rotation": [0, 0, 0], "scale": 1.0,
       "color_override": [0.9, 0.9, 0.1, 1.0]}
    ]})",
                             "/data/scenes/a.json");
  CHECK(s.background == glm::vec3(0.1f, 0.2f, 0.3f));
  CHECK(s.width == 320);
  CHECK(s.height == 200);
  CHECK(s.camera.fovYDegrees == 45.0f);
  CHECK(s.camera.up == glm::vec3(0, 1, 0));
  REQUIRE(s.objects.size() == 2);
  CHECK(s.objects[0].filePath == "/data/scenes/meshes/quad.obj");
  CHECK(s.objects[0].isTransparent());
  CHECK(s.objects[1].type == ObjectType::Particles);
  CHECK(s.objects[1].particleCount == 16);
  CHECK(s.objects[1].seed == 1);
  CHECK(s.objects[1].isTransparent());  // soft edges, whatever the override's alpha
}

TEST_CASE("scene: bad input names the file and the field", "[scene]") {
  CHECK_THAT(errorOf("{\"objects\": [}"), Catch::StartsWith("s.json: malformed JSON"));
  CHECK_THAT(errorOf("{}"), Catch::Contains("s.json: objects: expected an array"));
  CHECK_THAT(errorOf(R"({"objects": [], "bak": [0,0,0]})"), Catch::Contains("bak: unknown key (did you mean 'back'?)"));
  CHECK_THAT(errorOf(R"({"objects": [{"type": "mesh", "file_path": "a.obj", "colour_override": [1,1,1,1]}]})"),
             Catch::Contains("objects[0].colour_override: unknown key (did you mean 'color_override'?)"));
  CHECK_THAT(errorOf(R"({"objects": [{"type": "mesh", "file_path": "a.obj", "color_override": [1,1,"x",1]}]})"),
             Catch::Contains("objects[0].color_override[2]: expected a number, got string"));
  CHECK_THAT(errorOf(R"({"objects": [{"type": "mesh", "file_path": "a.obj", "color_override": [1,1,1,2]}]})"),
             Catch::Contains("objects[0].color_override[3]: alpha must lie in [0, 1]"));
  CHECK_THAT(errorOf(R"({"objects": [{"type": "cube"}]})"), Catch::Contains("objects[0].type: unknown object type 'cube'"));
  CHECK_THAT(errorOf(R"({"objects": [{"type": "particle"}]})"), Catch::Contains("objects[0].count: missing"));
  CHECK_THAT(errorOf(R"({"objects": [{"type": "particle", "count": -3}]})"), Catch::Contains("objects[0].count: expected an integer in [0"));
  CHECK_THAT(errorOf(R"({"objects": [], "resolution": [0, 10]})"), Catch::Contains("resolution[0]: expected an integer in [1, 16384]"));
  CHECK_THAT(errorOf(R"({"objects": [], "resolution": [100000, 10]})"), Catch::Contains("resolution[0]"));
  CHECK_THAT(errorOf(R"({"objects": [], "camera": {"near": 0}})"), Catch::Contains("camera.near: must be positive"));
  CHECK_THAT(errorOf(R"({"objects": [], "camera": {"near": 2, "far": 1}})"), Catch::Contains("camera.far: must be greater than near"));
  CHECK_THAT(errorOf(R"({"objects": [], "camera": {"fov_y": 180}})"), Catch::Contains("camera.fov_y: must lie in (0, 180)"));
  CHECK_THAT(errorOf(R"({"objects": [], "camera": {"up": [0, 0, 0]}})"), Catch::Contains("camera.up: must not be zero"));
  CHECK_THAT(errorOf(R"({"objects": [], "camera": {"position": [0,5,0], "target": [0,0,0]}})"),
             Catch::Contains("camera.up: must not be parallel"));
  CHECK_THAT(errorOf(R"({"objects": [{"type": "mesh", "file_path": "a.obj", "scale": 0}]})"), Catch::Contains("objects[0].scale: must be positive"));
  CHECK_THROWS_WITH(loadScene("/nonexistent/scene.json"), Catch::Contains("/nonexistent/scene.json: cannot read"));
  const std::string missingMesh = write("missing_mesh.json", R"({"objects": [{"type": "mesh", "file_path": "nope.obj"}]})");
  CHECK_THROWS_WITH(loadScene(missingMesh), Catch::Contains("objects[0].file_path: mesh file") && Catch::Contains("nope.obj' does not exist"));
}

TEST_CASE("scene: the model matrix is T·Rz·Ry·Rx·S", "[scene]") {
  SceneObject o;
  o.rotationDegrees = {90, 0, 90};
  // Rx first: (0,1,0) -> (0,0,1), which Rz leaves alone. (Rz first would give (-1,0,0).)
  glm::vec4 v = o.modelMatrix() * glm::vec4(0, 1, 0, 1);
  CHECK(v.x == Approx(0).margin(1e-6));
  CHECK(v.y == Approx(0).margin(1e-6));
  CHECK(v.z == Approx(1).margin(1e-6));
  o.rotationDegrees = {0, 90, 0};
  o.scale = 2;
  o.position = {10, 20, 30};
  // S then Ry(90): (1,0,0) -> (2,0,0) -> (0,0,-2); then T.
  v = o.modelMatrix() * glm::vec4(1, 0, 0, 1);
  CHECK(v.x == Approx(10).margin(1e-5));
  CHECK(v.y == Approx(20).margin(1e-5));
  CHECK(v.z == Approx(28).margin(1e-5));
}

// Issue 21: a particle cloud's rotation was read and ignored. It turns the cloud's centres about
// its position (the model matrix, as for meshes); the quads keep facing the camera. Checked against
// the rotation written out by hand: Rz(90°) maps (x, y, z) to (−y, x, z).
TEST_CASE("scene: a particle cloud's rotation turns its centres about its position", "[scene]") {
  Scene scene;
  SceneObject o;
  o.type = ObjectType::Particles;
  o.particleCount = 20;
  o.seed = 7;
  o.position = {1.0f, -2.0f, 0.5f};
  o.scale = 3.0f;
  scene.objects.push_back(o);
  o.rotationDegrees = {0.0f, 0.0f, 90.0f};
  scene.objects.push_back(o);
  const SceneGeometry g = buildSceneGeometry(scene);
  REQUIRE(g.parts.size() == 2);
  const ScenePart &plain = g.parts[0], &turned = g.parts[1];
  REQUIRE(plain.positions.size() == 80);
  REQUIRE(turned.positions.size() == 80);
  int moved = 0;
  for (size_t q = 0; q < 20; ++q) {
    glm::dvec3 c0(0.0), c1(0.0);  // the quads' centres
    for (size_t v = 0; v < 4; ++v) c0 += glm::dvec3(plain.positions[4 * q + v]) / 4.0, c1 += glm::dvec3(turned.positions[4 * q + v]) / 4.0;
    const glm::dvec3 p = c0 - glm::dvec3(o.position), expected = glm::dvec3(o.position) + glm::dvec3(-p.y, p.x, p.z);
    CHECK(glm::length(c1 - expected) < 1e-5);
    moved += glm::length(c1 - c0) > 1e-3;
    // Each quad is the same billboard, moved: its edges do not turn.
    for (size_t v = 1; v < 4; ++v) {
      const glm::dvec3 e0 = glm::dvec3(plain.positions[4 * q + v]) - glm::dvec3(plain.positions[4 * q]);
      const glm::dvec3 e1 = glm::dvec3(turned.positions[4 * q + v]) - glm::dvec3(turned.positions[4 * q]);
      CHECK(glm::length(e1 - e0) < 1e-5);
    }
  }
  CHECK(moved == 20);
}

TEST_CASE("scene: meshes load through Assimp from OBJ, PLY (ascii, binary, colours), glTF and FBX", "[scene]") {
  const std::string obj = write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  TriangleMesh m = loadMesh(obj);
  CHECK(m.positions.size() == 4);
  CHECK(m.indices.size() == 6);  // the quad triangulated
  CHECK(m.colors[0] == glm::vec4(1.0f));

  const std::string ply = write("tri.ply",
                                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
                                "property uchar alpha\nelement face 1\nproperty list uchar int vertex_indices\n"
                                "end_header\n0 0 0 255 0 0 128\n1 0 0 0 255 0 255\n0 1 0 0 0 255 0\n3 0 1 2\n");
  m = loadMesh(ply);
  REQUIRE(m.positions.size() == 3);
  CHECK(m.colors[0].r == Approx(1.0f));
  CHECK(m.colors[0].a == Approx(128.0f / 255.0f));
  CHECK(m.colors[2].b == Approx(1.0f));

  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float p[3][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  for (int v = 0; v < 3; ++v) {
    bin.append(reinterpret_cast<const char*>(p[v]), 12);
    const uint8_t c[4] = {10, 20, 30, uint8_t(v == 1 ? 64 : 255)};
    bin.append(reinterpret_cast<const char*>(c), 4);
  }
  bin += char(3);
  const int32_t idx[3] = {0, 1, 2};
  bin.append(reinterpret_cast<const char*>(idx), 12);
  m = loadMesh(write("tri_bin.ply", bin));
  REQUIRE(m.positions.size() == 3);
  CHECK(m.positions[1].x == 2.0f);
  CHECK(m.colors[1].a == Approx(64.0f / 255.0f));

  std::vector<uint8_t> buffer(36);
  const float gp[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::memcpy(buffer.data(), gp, 36);
  const std::string gltf = write("tri.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "translation": [0, 0, 5]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,)" + base64(buffer) + R"("}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]}]})");
  m = loadMesh(gltf);
  REQUIRE(m.positions.size() == 3);
  CHECK(m.positions[0].z == 5.0f);  // the node transform is applied
  // FBX: a binary file from Assimp's own test models (tests/data/README.md).
  m = loadMesh(OITREF_SOURCE_DIR "/tests/data/box.fbx");
  CHECK(m.indices.size() == 36);  // a cube: 12 triangles
  CHECK(m.positions.size() == 36);
  CHECK_THROWS_WITH(loadMesh(write("bad.obj", "this is not a mesh\n")), Catch::Contains("bad.obj"));
}

TEST_CASE("scene: particles are seeded, inside their sphere, and face the camera", "[scene]") {
  Scene s;
  s.camera.position = {3, 4, 12};
  s.camera.target = {0, 0, 0};
  SceneObject o;
  o.type = ObjectType::Particles;
  o.particleCount = 200;
  o.seed = 7;
  o.position = {1, 2, 3};
  o.scale = 2.5f;
  o.particleSize = 0.4f;
  s.objects.push_back(o);
  const SceneGeometry a = buildSceneGeometry(s), b = buildSceneGeometry(s);
  REQUIRE(a.parts[0].triangleCount() == 400);
  CHECK(a.parts[0].positions == b.parts[0].positions);  // deterministic
  const glm::vec3 view = glm::normalize(s.camera.target - s.camera.position);
  for (size_t q = 0; q < 200; ++q) {
    const glm::vec3* c = &a.parts[0].positions[q * 4];
    const glm::vec3 centre = (c[0] + c[2]) * 0.5f;
    CHECK(glm::length(centre - o.position) <= 2.5f + 1e-5f);
    CHECK(glm::length(c[1] - c[0]) == Approx(0.4f).epsilon(1e-5));
    CHECK(std::abs(glm::dot(glm::normalize(glm::cross(c[1] - c[0], c[3] - c[0])), view)) == Approx(1.0f).epsilon(1e-5));
  }
  s.objects[0].seed = 8;
  CHECK(buildSceneGeometry(s).parts[0].positions != a.parts[0].positions);
}

TEST_CASE("scene: shading — overrides, vertex colours and the particle falloff", "[scene]") {
  SceneObject particle;
  particle.type = ObjectType::Particles;
  const float centre[6] = {1, 0.5f, 0.25f, 0.8f, 0.5f, 0.5f};
  CHECK(shadeSurface(particle, centre) == glm::vec4(1, 0.5f, 0.25f, 0.8f));
  const float edge[6] = {1, 1, 1, 0.8f, 1.0f, 0.5f};  // r = 1
  CHECK(shadeSurface(particle, edge).a == 0.0f);
  const float corner[6] = {1, 1, 1, 0.8f, 0.0f, 0.0f};
  CHECK(shadeSurface(particle, corner).a == 0.0f);
  const float half[6] = {1, 1, 1, 1.0f, 0.75f, 0.5f};  // r = 0.5: (1 − 0.25)² = 0.5625
  CHECK(shadeSurface(particle, half).a == 0.5625f);
  SceneObject mesh;
  mesh.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.mesh.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 0.5f}};
  mesh.mesh.indices = {0, 1, 2};
  CHECK(mesh.isTransparent());
  mesh.transparentOverride = false;
  CHECK_FALSE(mesh.isTransparent());
  Scene s;
  s.objects.push_back(mesh);
  const SceneGeometry g = buildSceneGeometry(s);
  CHECK(g.parts[0].attributes[2 * kSceneAttributeCount + 3] == 0.5f);  // the vertex colour's alpha
  s.objects[0].colorOverride = glm::vec4(0.2f, 0.3f, 0.4f, 1.0f);
  CHECK(buildSceneGeometry(s).parts[0].attributes[2 * kSceneAttributeCount + 3] == 1.0f);
}

TEST_CASE("scene: shadeSurfaceBatch gives shadeSurface's bits for every fragment of a batch", "[scene]") {
  // Rows of 21 fragments (two groups of eight and a rest): meshes and particles, their colours
  // varying or one value in every fragment (the `uniform` bits, which only let it read them once).
  constexpr int N = 21, S = 32;  // fragments, row stride
  for (ObjectType type : {ObjectType::Mesh, ObjectType::Particles})
    for (bool uniformColour : {false, true}) {
      SceneObject object;
      object.type = type;
      float rows[kSceneAttributeCount * S] = {};
      for (int i = 0; i < N; ++i) {
        for (int k = 0; k < 4; ++k) rows[k * S + i] = uniformColour ? 0.3f + 0.1f * float(k) : float(i * 7 + k) / 97.0f;
        rows[4 * S + i] = float(i) / float(N - 1);       // u across the quad
        rows[5 * S + i] = float((i * 5) % N) / float(N);  // v
      }
      glm::vec4 got[N];
      shadeSurfaceBatch(object, rows, S, nullptr, 1, TextureFiltering::Exact, N, got, uniformColour ? 0xFu : 0u);
      for (int i = 0; i < N; ++i) {
        const glm::vec4 want = shadeSurface(object, rows + i, S);
        INFO((type == ObjectType::Particles ? "particles" : "mesh") << (uniformColour ? ", one colour" : "") << ", fragment " << i);
        CHECK(std::memcmp(&got[i], &want, sizeof want) == 0);
      }
    }
}
