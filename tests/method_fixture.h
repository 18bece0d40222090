// The test scene of the method tests and the closed forms' plumbing: the A-buffer's fragment
// lists per pixel, the background C0 without the transparent objects, and a checked comparison.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "oitref/oit/frame.h"
#include "oitref/oit/method.h"

namespace oitref::test {

inline TriangleMesh quadMesh() {
  TriangleMesh m;
  m.positions = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
  m.colors.assign(4, glm::vec4(1.0f));
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

inline SceneObject quad(glm::vec3 position, float scale, glm::vec4 color, glm::vec3 rotation = glm::vec3(0)) {
  SceneObject o;
  o.mesh = quadMesh();
  o.position = position;
  o.scale = scale;
  o.colorOverride = color;
  o.rotationDegrees = rotation;
  return o;
}

// A 8 × 8 RGBA8 texture whose texels all differ, alpha from 0 to 252 (the closed forms' fragment
// lists carry the sampled colour and alpha), with its mipmaps.
inline std::shared_ptr<const Texture2D> patternTexture() {
  std::vector<uint8_t> texels(8 * 8 * 4);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      uint8_t* t = &texels[size_t(j * 8 + i) * 4];
      t[0] = uint8_t(32 * i + 16), t[1] = uint8_t(255 - 30 * j), t[2] = uint8_t((i * j * 11) % 256), t[3] = uint8_t(4 * ((i * 37 + j * 91) % 64));
    }
  auto texture = std::make_shared<Texture2D>(TextureFormat::Rgba8, 8, 8, std::move(texels));
  texture->generateMipmaps();
  return texture;
}

// quad() with texture coordinates 0..repeat over it and the pattern texture (trilinear).
inline SceneObject texturedQuad(glm::vec3 position, float scale, glm::vec4 color, glm::vec3 rotation, float repeat) {
  SceneObject o = quad(position, scale, color, rotation);
  o.mesh.texcoords = {{0, 0}, {repeat, 0}, {repeat, repeat}, {0, repeat}};
  o.texture = patternTexture();
  o.textureFile = "pattern";
  o.sampler.minFilter = TextureFilter::LinearMipmapLinear;
  return o;
}

// A size × size view of full-screen layers at z ≤ 0 from the camera at (0, 0, 2), over
// `background`: the hand-derived cases.
inline Scene layerScene(int size, glm::vec3 background) {
  Scene s;
  s.width = s.height = size;
  s.background = background;
  s.camera.position = {0, 0, 2};
  s.camera.target = {0, 0, 0};
  return s;
}

// Overlapping, tilted and intersecting translucent quads (α from 0.05 to 0.95) and a particle
// cloud, over an opaque backdrop that a few quads reach behind.
inline Scene testScene() {
  Scene s;
  s.width = 64;
  s.height = 48;
  s.background = {0.2f, 0.3f, 0.4f};
  s.camera.position = {0, 0, 6};
  s.camera.target = {0, 0, 0};
  s.camera.fovYDegrees = 50;
  s.objects.push_back(quad({0, 0, -2}, 5, {0.8f, 0.7f, 0.2f, 1.0f}));
  s.objects.back().transparentOverride = false;
  s.objects.push_back(quad({-0.6f, 0.3f, 1.0f}, 2.0f, {1.0f, 0.1f, 0.1f, 0.35f}));
  s.objects.push_back(quad({0.5f, 0.2f, 0.2f}, 2.2f, {0.1f, 0.9f, 0.2f, 0.6f}, {0, 35, 0}));
  s.objects.push_back(quad({0.0f, -0.4f, -0.5f}, 2.5f, {0.2f, 0.2f, 1.0f, 0.9f}, {20, 0, 10}));
  s.objects.push_back(quad({-0.3f, -0.2f, 0.6f}, 1.5f, {1.0f, 1.0f, 1.0f, 0.05f}));
  s.objects.push_back(quad({0.2f, 0.1f, -2.6f}, 1.0f, {0.5f, 0.5f, 0.5f, 0.95f}));  // behind the backdrop
  // Textured: the texels' alpha (0 included) in the fragment lists; an alpha-tested one whose
  // discarded texels are no layer.
  s.objects.push_back(texturedQuad({0.4f, -0.3f, 0.8f}, 2.0f, {1.0f, 1.0f, 1.0f, 1.0f}, {0, -25, 0}, 3.0f));
  s.objects.push_back(texturedQuad({-0.5f, 0.4f, 0.3f}, 1.8f, {0.9f, 0.8f, 1.0f, 1.0f}, {15, 0, 0}, 1.5f));
  s.objects.back().alphaTest = 0.5f;
  SceneObject cloud;
  cloud.type = ObjectType::Particles;
  cloud.particleCount = 12;
  cloud.seed = 4;
  cloud.position = {0.3f, 0.0f, 1.5f};
  cloud.scale = 1.0f;
  cloud.particleSize = 0.6f;
  cloud.colorOverride = glm::vec4(0.9f, 0.9f, 0.9f, 0.7f);
  s.objects.push_back(cloud);
  return s;
}

struct Reference {
  Scene scene;
  FrameResult abuffer;
  Image background;  // C0 per pixel in fp32: the scene without its transparent objects
};

inline FrameResult render(const Scene& scene, const std::string& method, const std::map<std::string, std::string>& options = {},
                   int threads = 2) {
  Renderer r(RendererOptions{threads, 16});
  return SceneFrames(scene, r).render(*makeMethod(method, options));
}

inline const Reference& reference() {
  static const Reference ref = [] {
    Reference r;
    r.scene = testScene();
    r.abuffer = render(r.scene, "abuffer", {{"lists", "keep"}});
    Scene opaqueOnly = r.scene;
    std::erase_if(opaqueOnly.objects, [](const SceneObject& o) { return o.isTransparent(); });
    r.background = render(opaqueOnly, "over").finalFloat;
    return r;
  }();
  return ref;
}

// Calls check(x, y, fragments, C0) for every pixel.
template <typename Check>
inline void forEachPixel(const Check& check) {
  const Reference& ref = reference();
  const int w = ref.scene.width;
  for (int y = 0; y < ref.scene.height; ++y)
    for (int x = 0; x < w; ++x) {
      const auto stored = ref.abuffer.fragmentLists.at(x, y);
      std::vector<TransparentFragment> f(stored.begin(), stored.end());
      check(x, y, f, glm::dvec3(glm::vec3(ref.background.fetch(x, y))));
    }
}

inline void requireClose(const Image& got, int x, int y, const glm::dvec3& want, double bound, const char* what) {
  const glm::vec4 g = got.fetch(x, y);
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(double(g[k]) - want[k]) <= bound))
      FAIL(what << " pixel " << x << "," << y << " channel " << k << ": got " << g[k] << ", closed form " << want[k]
                << ", bound " << bound);
}

inline glm::dvec3 overBackToFront(std::vector<TransparentFragment> f, glm::dvec3 c) {
  std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.viewDepth < b.viewDepth; });
  for (size_t i = f.size(); i-- > 0;) c = glm::dvec3(glm::vec3(f[i].color)) * double(f[i].color.a) + c * (1.0 - f[i].color.a);
  return c;
}

inline constexpr double kU32 = 1.0 / (1 << 24), kU16 = 1.0 / (1 << 11);

}  // namespace oitref::test
