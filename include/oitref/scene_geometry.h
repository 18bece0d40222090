// A scene's triangles in world space for its camera, with the attributes its shading reads, and
// the one shading function per object that both ground truths use (the rasterizer through a
// fragment shader, the ray caster at its hit points), so they differ only in visibility and
// interpolation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "oitref/geometry.h"
#include "oitref/scene.h"

namespace oitref {

// Per-vertex attributes: straight RGBA (the colour override, else the mesh's vertex colour),
// then the quad uv of particles (0, 0 for meshes).
inline constexpr int kSceneAttributeCount = 6;

struct ScenePart {
  size_t objectIndex = 0;
  bool transparent = false;
  std::vector<glm::vec3> positions;  // world space
  std::vector<float> attributes;     // kSceneAttributeCount per vertex
  std::vector<uint32_t> indices;     // three per triangle, in submission order
  size_t triangleCount() const { return indices.size() / 3; }
};

struct SceneGeometry {
  std::vector<ScenePart> parts;  // one per object, in the scene's object order
  size_t triangleCount() const;
};

// Particles face the scene's camera, so the geometry is built for it.
SceneGeometry buildSceneGeometry(const Scene& scene);

// The vertex stage: a part's triangles in clip space for the rasterizer.
Geometry toClipGeometry(const ScenePart& part, const glm::mat4& viewProjection);

// The object's straight RGBA at a surface point, from its interpolated attributes. Particles
// multiply alpha by a soft radial falloff of the quad uv: (1 − r²)² inside the inscribed
// circle (r = 1 at its edge), 0 outside. Only +, −, × are used: the same bits on every machine.
// Inline: every transparent fragment calls it. Attribute k at a[k · stride].
// shadeSurfaceReads(object) is how many of the leading attributes it reads for the object.
inline int shadeSurfaceReads(const SceneObject& object) { return object.type == ObjectType::Particles ? kSceneAttributeCount : 4; }
inline glm::vec4 shadeSurface(const SceneObject& object, const float* a, int stride = 1) {
  glm::vec4 c(a[0], a[stride], a[2 * stride], a[3 * stride]);
  if (object.type == ObjectType::Particles) {
    const float x = 2.0f * a[4 * stride] - 1.0f, y = 2.0f * a[5 * stride] - 1.0f;
    const float r2 = x * x + y * y;
    const float falloff = r2 < 1.0f ? (1.0f - r2) * (1.0f - r2) : 0.0f;
    c.a = c.a * falloff;
  }
  return c;
}

}  // namespace oitref
