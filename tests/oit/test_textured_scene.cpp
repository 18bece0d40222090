// Textured scenes end to end: the texture coordinates through the pipeline, the level of detail
// from the quad's derivatives, the alpha test, the ray cast's agreement, and the scene file's
// texture fields and their errors. Expected values are closed forms of the view (a quad facing
// the camera, whose texture coordinates are affine in the window), not recorded output.
#include <catch2/catch.hpp>
#include <zlib.h>

#include <cmath>

#include "method_fixture.h"
#include "oitref/oit/scene_geometry.h"
#include "temp_files.h"
#include "oitref/oit/image_io.h"

using namespace oitref;

namespace {

// 64 × 64 pixels, fov_y 90°, camera at z = 2 looking at a quad of side 2 at z = 0 that covers
// the middle 32 × 32 pixels: a pixel is 1/16 of a unit there, so texture coordinates 0..repeat
// over the quad change by repeat/32 per pixel, and a w-texel-wide texture has ρ = w·repeat/32.
Scene facingQuad(std::shared_ptr<const Texture2D> texture, SamplerState sampler, float repeat) {
  Scene s = test::layerScene(64, {0.0f, 0.0f, 0.0f});
  s.camera.fovYDegrees = 90.0f;
  SceneObject q = test::quad({0, 0, 0}, 2.0f, glm::vec4(1.0f));
  q.mesh.texcoords = {{0, 0}, {repeat, 0}, {repeat, repeat}, {0, repeat}};
  q.texture = std::move(texture);
  q.textureFile = "test";
  q.sampler = sampler;
  q.transparentOverride = false;
  s.objects.push_back(q);
  return s;
}

// A 64 × 64 texture whose level i is the solid colour (10·i, 255 − 10·i, 3·i) / 255.
std::shared_ptr<Texture2D> levelColours() {
  auto solid = [](int size, int i) {
    std::vector<uint8_t> t(size_t(size) * size_t(size) * 4);
    for (size_t p = 0; p < t.size(); p += 4) t[p] = uint8_t(10 * i), t[p + 1] = uint8_t(255 - 10 * i), t[p + 2] = uint8_t(3 * i), t[p + 3] = 255;
    return t;
  };
  auto texture = std::make_shared<Texture2D>(TextureFormat::Rgba8, 64, 64, solid(64, 0));
  for (int i = 1; i <= 6; ++i) texture->setLevel(i, TextureLevel{64 >> i, 64 >> i, solid(64 >> i, i)});
  return texture;
}

glm::vec3 levelColour(int i) { return glm::vec3(float(10 * i) / 255.0f, float(255 - 10 * i) / 255.0f, float(3 * i) / 255.0f); }

FrameResult renderWith(const Scene& scene, const std::string& method) { return test::render(scene, method); }

}  // namespace

TEST_CASE("textured scene: the level of detail is log2 of the quad's derivatives in texels", "[texture][scene]") {
  SamplerState sampler;
  sampler.minFilter = TextureFilter::NearestMipmapNearest;
  sampler.magFilter = TextureFilter::Nearest;
  // ρ = 64·repeat/32 = 2·repeat; λ = log2 ρ; §8.14.3: level ⌈λ + ½⌉ − 1, level 0 when magnified.
  for (const float repeat : {0.25f, 1.0f, 2.0f, 8.0f, 16.0f}) {
    const double lambda = std::log2(2.0 * repeat);
    const int level = lambda <= 0.5 ? 0 : int(std::ceil(lambda + 0.5)) - 1;
    const Scene scene = facingQuad(levelColours(), sampler, repeat);
    for (const std::string method : {"opaque", "raycast"}) {
      const FrameResult frame = renderWith(scene, method);
      INFO(method << ", repeat " << repeat << ": λ " << lambda << ", level " << level);
      for (int y = 17; y < 47; ++y)
        for (int x = 17; x < 47; ++x) REQUIRE(glm::vec3(frame.finalFloat.fetch(x, y)) == levelColour(level));
    }
  }
}

TEST_CASE("textured scene: a magnified NEAREST texture shows the texel under each pixel centre", "[texture][scene]") {
  std::vector<uint8_t> texels(64 * 64 * 4);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      uint8_t* t = &texels[size_t(j * 64 + i) * 4];
      t[0] = uint8_t(4 * i), t[1] = uint8_t(4 * j), t[2] = uint8_t((i * 7 + j * 13) % 256), t[3] = 255;
    }
  SamplerState sampler;
  sampler.minFilter = sampler.magFilter = TextureFilter::Nearest;
  // repeat 0.25: u = 0.25·(x + ½ − 16)/32 at pixel x, texel ⌊64u⌋ = ⌊(x − 15.5)/2⌋, never a tie.
  const Scene scene = facingQuad(std::make_shared<Texture2D>(TextureFormat::Rgba8, 64, 64, texels), sampler, 0.25f);
  for (const std::string method : {"opaque", "raycast"}) {
    const FrameResult frame = renderWith(scene, method);
    for (int y = 16; y < 48; ++y)
      for (int x = 16; x < 48; ++x) {
        const int i = int(std::floor((x - 15.5) / 2.0)), j = int(std::floor((y - 15.5) / 2.0));
        const uint8_t* t = &texels[size_t(j * 64 + i) * 4];
        INFO(method << " pixel " << x << "," << y << ": texel " << i << "," << j);
        REQUIRE(glm::vec3(frame.finalFloat.fetch(x, y)) == glm::vec3(float(t[0]) / 255.0f, float(t[1]) / 255.0f, float(t[2]) / 255.0f));
      }
  }
}

TEST_CASE("textured scene: the alpha test discards texels below its threshold, in every ground truth", "[texture][scene]") {
  // Alpha 0 on the left half of the texture, 255 on the right; texel colour white.
  std::vector<uint8_t> texels(8 * 8 * 4, 255);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 4; ++i) texels[size_t(j * 8 + i) * 4 + 3] = 0;
  SamplerState sampler;
  sampler.minFilter = sampler.magFilter = TextureFilter::Nearest;
  Scene scene = facingQuad(std::make_shared<Texture2D>(TextureFormat::Rgba8, 8, 8, texels), sampler, 1.0f);
  scene.background = {0.25f, 0.5f, 0.75f};
  scene.objects[0].colorOverride = glm::vec4(0.5f, 0.25f, 1.0f, 1.0f);
  scene.objects[0].alphaTest = 0.5f;
  // u = (x + ½ − 16)/32 inside the quad; texel ⌊8u⌋ < 4 (discarded) for x < 32.
  for (const std::string method : {"opaque", "over", "abuffer", "raycast"}) {
    const FrameResult frame = renderWith(scene, method);
    for (int y = 17; y < 47; ++y)
      for (int x = 17; x < 47; ++x) {
        INFO(method << " pixel " << x << "," << y);
        REQUIRE(glm::vec3(frame.finalFloat.fetch(x, y)) == (x < 32 ? scene.background : glm::vec3(0.5f, 0.25f, 1.0f)));
      }
  }
}

TEST_CASE("textured scene: a texel's alpha below 1 makes the object transparent", "[texture][scene]") {
  std::vector<uint8_t> texels(4 * 4 * 4, 255);
  SceneObject o = test::quad({0, 0, 0}, 1.0f, glm::vec4(1.0f));
  o.colorOverride.reset();
  o.texture = std::make_shared<Texture2D>(TextureFormat::Rgba8, 4, 4, texels);
  CHECK_FALSE(o.isTransparent());
  texels[4 * 5 + 3] = 254;
  o.texture = std::make_shared<Texture2D>(TextureFormat::Rgba8, 4, 4, texels);
  CHECK(o.isTransparent());
}

TEST_CASE("textured scene: textures load beside the model, and bad ones are errors naming the file", "[texture][scene]") {
  const auto dir = test::tempFolder("oitref-texture-scene");
  // A 2 × 2 texture, its file's top row first: row 1 (t = 1) red, green; row 0 blue, white.
  Image png(makeFormat(FormatId::RGBA8), 2, 2);
  png.store(0, 1, {1, 0, 0, 1}, exactProfile()), png.store(1, 1, {0, 1, 0, 1}, exactProfile());
  png.store(0, 0, {0, 0, 1, 1}, exactProfile()), png.store(1, 0, {1, 1, 1, 0.5f}, exactProfile());
  writeImage((dir / "tex.png").string(), png);
  const std::string quadUv = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
  test::writeFile(dir, "m.mtl", "newmtl a\nmap_Kd tex.png\nnewmtl b\nmap_Kd other.png\n");
  test::writeFile(dir, "textured.obj", "mtllib m.mtl\nusemtl a\n" + quadUv + "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
  test::writeFile(dir, "plain.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nf 1 2 3\n");
  test::writeFile(dir, "uv.obj", quadUv + "f 1/1 2/2 3/3\n");
  test::writeFile(dir, "two.obj", "mtllib m.mtl\n" + quadUv + "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 4/4\n");
  test::writeFile(dir, "missing.mtl", "newmtl a\nmap_Kd nowhere.png\n");
  test::writeFile(dir, "missing.obj", "mtllib missing.mtl\nusemtl a\n" + quadUv + "f 1/1 2/2 3/3\n");
  auto scene = [&](const std::string& object) {
    return test::writeFile(dir, "s.json", R"({"resolution": [8, 8], "objects": [)" + object + "]}");
  };

  SECTION("the material's texture, rows from the bottom, mipmaps generated, alpha making it transparent") {
    const Scene s = loadScene(scene(R"({"type": "mesh", "file_path": "textured.obj"})"));
    const SceneObject& o = s.objects[0];
    REQUIRE(o.texture);
    CHECK(o.textureFile == (dir / "tex.png").lexically_normal().string());
    CHECK(o.texture->levels() == 2);
    CHECK(o.texture->texel(0, 0, 1) == glm::dvec4(1, 0, 0, 1));
    CHECK(o.texture->texel(0, 1, 0).a == 128.0 / 255.0);
    CHECK(o.mesh.texcoords.size() == o.mesh.positions.size());
    CHECK(o.isTransparent());
  }
  SECTION("the scene's texture, format and sampler") {
    const Scene s = loadScene(scene(R"({"type": "mesh", "file_path": "uv.obj", "transparent": false,
        "texture": "tex.png", "texture_format": "srgb8_alpha8", "alpha_test": 0.25,
        "sampler": {"min_filter": "linear_mipmap_nearest", "mag_filter": "nearest", "wrap_s": "mirrored_repeat", "lod_bias": 1.5}})"));
    const SceneObject& o = s.objects[0];
    CHECK(o.texture->format() == TextureFormat::Srgb8Alpha8);
    CHECK(o.sampler.minFilter == TextureFilter::LinearMipmapNearest);
    CHECK(o.sampler.magFilter == TextureFilter::Nearest);
    CHECK(o.sampler.wrapS == WrapMode::MirroredRepeat);
    CHECK(o.sampler.wrapT == WrapMode::Repeat);
    CHECK(o.sampler.lodBias == 1.5f);
    CHECK(o.alphaTest == 0.25f);
  }
  // plain.obj has no texture coordinates: a texture on it is refused.
  auto fails = [&](const std::string& object, const std::string& what) {
    const std::string path = scene(object);
    REQUIRE_THROWS_AS(loadScene(path), SceneError);
    try {
      loadScene(path);
    } catch (const SceneError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(what) != std::string::npos);
    }
  };
  fails(R"({"type": "mesh", "file_path": "plain.obj", "texture": "tex.png"})", "objects[0].texture: the model '");
  fails(R"({"type": "mesh", "file_path": "textured.obj", "texture": "absent.png"})", "absent.png' does not exist");
  fails(R"({"type": "mesh", "file_path": "missing.obj"})", "names a texture: texture '" + (dir / "nowhere.png").string());
  fails(R"({"type": "mesh", "file_path": "two.obj"})", "has the diffuse texture '" + (dir / "other.png").string());
  fails(R"({"type": "mesh", "file_path": "plain.obj", "alpha_test": 0.5})", "objects[0].alpha_test: the object has no texture");
  fails(R"({"type": "mesh", "file_path": "textured.obj", "alpha_test": 1.5})", "objects[0].alpha_test: must lie in [0, 1]");
  fails(R"({"type": "mesh", "file_path": "textured.obj", "texture_format": "rgb8"})", "objects[0].texture_format: expected");
  fails(R"({"type": "mesh", "file_path": "textured.obj", "sampler": {"min_filtr": "linear"}})", "objects[0].sampler.min_filtr: unknown key");
  fails(R"({"type": "mesh", "file_path": "textured.obj", "sampler": {"mag_filter": "linear_mipmap_linear"}})",
        "objects[0].sampler.mag_filter: must be nearest or linear");
  fails(R"({"type": "mesh", "file_path": "textured.obj", "sampler": {"wrap_s": "clamp"}})", "unknown wrap mode 'clamp'");
  fails(R"({"type": "mesh", "file_path": "textured.obj", "texture": "m.mtl"})", "m.mtl': cannot read the image");

  // Declared sizes refused before any pixel is read: a 74-byte PNG whose header says 16384x16384
  // RGBA8 (1.2 GB and 3.5 s to fail inside libpng before), and a texture above the memory limit.
  auto pngChunk = [](const std::string& type, const std::string& data) {
    auto be32 = [](uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; };
    const std::string body = type + data;
    return be32(uint32_t(data.size())) + body + be32(uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
  };
  const std::string ihdr = std::string("\0\0\x40\0\0\0\x40\0", 8) + std::string("\x08\x06\0\0\0", 5);  // 16384², RGBA8
  const std::string idat = std::string("\x78\x9c\x63\x00\x00\x00\x01\x00\x01", 9);  // zlib: one zero byte
  test::writeFile(dir, "huge.png", "\x89PNG\r\n\x1a\n" + pngChunk("IHDR", ihdr) + pngChunk("IDAT", idat) + pngChunk("IEND", ""));
  // 16384 rows of a filter byte and 65536 sample bytes: 1,073,758,208 raw bytes.
  fails(R"({"type": "mesh", "file_path": "uv.obj", "texture": "huge.png"})",
        "huge.png': its PNG header declares 16384x16384 with 4 channels of 8 bits, 1073758208 bytes before compression, "
        "which no PNG of 66 bytes can hold");
  // The most a PNG can be compressed still loads: 512x512 zeros (RGBA8: 1,049,088 raw bytes).
  writeImage((dir / "zeros.png").string(), Image(makeFormat(FormatId::RGBA8), 512, 512));
  CHECK(loadScene(scene(R"({"type": "mesh", "file_path": "uv.obj", "texture": "zeros.png"})")).objects[0].texture);
  // 2x2 RGBA8 (tex.png): 16 bytes read, 16 kept: 32 B.
  const std::string small = scene(R"({"type": "mesh", "file_path": "uv.obj", "texture": "tex.png"})");
  CHECK_THROWS_WITH(loadScene(small, 31), Catch::Contains("tex.png': 2x2 with 4 channels needs at least 32 B to load, above the "
                                                          "memory limit of 31 B (--memory-limit)"));
  CHECK(loadScene(small, 32).objects[0].texture);
}
