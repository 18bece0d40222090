#include "oitref/oit/scene_geometry.h"

#include "util/seeded_random.h"


#include <glm/geometric.hpp>

namespace oitref {
namespace {

void pushVertex(ScenePart& part, const glm::vec3& p, const glm::vec4& color, glm::vec2 uv) {
  part.positions.push_back(p);
  const float a[kSceneAttributeCount] = {color.r, color.g, color.b, color.a, uv.x, uv.y};
  part.attributes.insert(part.attributes.end(), a, a + kSceneAttributeCount);
}

ScenePart meshPart(const SceneObject& o) {
  ScenePart part;
  const glm::dmat4 model(o.modelMatrix());
  for (size_t v = 0; v < o.mesh.positions.size(); ++v) {
    const glm::dvec4 w = model * glm::dvec4(glm::dvec3(o.mesh.positions[v]), 1.0);
    const glm::vec2 uv = v < o.mesh.texcoords.size() ? o.mesh.texcoords[v] : glm::vec2(0.0f);
    pushVertex(part, glm::vec3(w), o.colorOverride.value_or(o.mesh.colors[v]), uv);
  }
  part.indices = o.mesh.indices;
  return part;
}

ScenePart particlePart(const SceneObject& o, const Camera& camera) {
  ScenePart part;
  const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target - camera.position));
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
  const glm::dvec3 up = glm::cross(right, forward);
  const double half = 0.5 * double(o.particleSize);
  const glm::vec4 color = o.colorOverride.value_or(glm::vec4(1.0f));
  // The cloud is placed as a mesh is: its centres, drawn in the unit ball, through the model
  // matrix (T·Rz·Ry·Rx·S), so `rotation` turns the cloud about `position`. The quads stay
  // billboards facing the camera. Without a rotation the matrix's products with its zeros and
  // ones are exact: the centres are position + p·scale, bit for bit as before rotation counted.
  const glm::dmat4 model(o.modelMatrix());
  util::SeededRandom rng(o.seed);
  for (int i = 0; i < o.particleCount; ++i) {
    glm::dvec3 p;
    do {  // uniform in the unit ball, by rejection
      p = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    } while (glm::dot(p, p) > 1.0);
    const glm::dvec3 c = glm::dvec3(model * glm::dvec4(p, 1.0));
    const uint32_t base = uint32_t(part.positions.size());
    pushVertex(part, glm::vec3(c - right * half - up * half), color, {0, 0});
    pushVertex(part, glm::vec3(c + right * half - up * half), color, {1, 0});
    pushVertex(part, glm::vec3(c + right * half + up * half), color, {1, 1});
    pushVertex(part, glm::vec3(c - right * half + up * half), color, {0, 1});
    part.indices.insert(part.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  return part;
}

}  // namespace

glm::vec4 sampleSurfaceTexture(const SceneObject& object, float s, float t, const double* d, int stride,
                               TextureFiltering filtering) {
  const TextureLevel& base = object.texture->level(0);
  // llvmpipe's λ from its quad differences (fp32 values, which the stage's llvmpipe derivatives are).
  const double lod = !d                                       ? 0.0
                     : filtering == TextureFiltering::Llvmpipe ? double(llvmpipeLod(float(d[0]), float(d[stride]), float(d[2 * stride]),
                                                                                  float(d[3 * stride]), base.width, base.height))
                                                               : lodFromDerivatives(d[0], d[stride], d[2 * stride], d[3 * stride], base.width, base.height);
  return sampleTexture(*object.texture, object.sampler, s, t, lod, filtering);
}

size_t SceneGeometry::triangleCount() const {
  size_t n = 0;
  for (const ScenePart& p : parts) n += p.triangleCount();
  return n;
}

SceneGeometry buildSceneGeometry(const Scene& scene) {
  SceneGeometry g;
  g.camera = scene.camera;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    ScenePart part = o.type == ObjectType::Mesh ? meshPart(o) : particlePart(o, scene.camera);
    part.objectIndex = i;
    part.transparent = o.isTransparent();
    part.alphaTested = o.alphaTest.has_value();
    g.parts.push_back(std::move(part));
  }
  return g;
}

Geometry toClipGeometry(const ScenePart& part, const glm::mat4& viewProjection) {
  Geometry g = Geometry::fromVertexShader(part.positions.size(), kSceneAttributeCount, [&](size_t v, float* out) {
    for (int k = 0; k < kSceneAttributeCount; ++k) out[k] = part.attributes[v * kSceneAttributeCount + size_t(k)];
    return viewProjection * glm::vec4(part.positions[v], 1.0f);
  });
  g.indices = part.indices;
  return g;
}

}  // namespace oitref
