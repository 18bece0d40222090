// A scene's triangles in world space for its camera, with the attributes its shading reads, and
// the one shading function per object that both ground truths use (the rasterizer through a
// fragment shader, the ray caster at its hit points), so they differ only in visibility and
// interpolation.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "oitref/core/geometry.h"
#include "oitref/oit/scene.h"

namespace oitref {

// Per-vertex attributes: straight RGBA (the colour override, else the mesh's vertex colour),
// then the texture coordinates (s, t): a mesh's first set (0, 0 without one), a particle's quad
// corner.
inline constexpr int kSceneAttributeCount = 6;

struct ScenePart {
  size_t objectIndex = 0;
  bool transparent = false;
  bool alphaTested = false;          // its fragments may be discarded (the object's alpha test)
  std::vector<glm::vec3> positions;  // world space
  std::vector<float> attributes;     // kSceneAttributeCount per vertex
  std::vector<uint32_t> indices;     // three per triangle, in submission order
  size_t triangleCount() const { return indices.size() / 3; }
};

struct SceneGeometry {
  std::vector<ScenePart> parts;  // one per object, in the scene's object order
  Camera camera;                 // the camera it was built for
  size_t triangleCount() const;
};

// Particles face the scene's camera, so the geometry is built for it.
SceneGeometry buildSceneGeometry(const Scene& scene);

// Why the rasterizer would lose geometry that the ray cast sees, or "": a surface no farther than
// half the far distance whose depth rounds onto the far plane (the depth clear's D24 code), where
// the LESS test against the clear fails (a near plane far too close for its far one). loadScene
// refuses such scenes (depth_precision.cpp).
std::string depthPrecisionProblem(const SceneGeometry& geometry);

// The vertex stage: a part's triangles in clip space for the rasterizer.
Geometry toClipGeometry(const ScenePart& part, const glm::mat4& viewProjection);

// The object's texture at (s, t), with the level of detail of the texture coordinates'
// derivatives d over the quad (FragmentInput::derivatives: ∂s/∂x, ∂t/∂x, ∂s/∂y, ∂t/∂y at
// d[i · stride]; level 0's λ = 0 without them), filtered by the profile's rule (Profile::texture).
glm::vec4 sampleSurfaceTexture(const SceneObject& object, float s, float t, const double* d, int stride,
                               TextureFiltering filtering);

// The object's straight RGBA at a surface point, from its interpolated attributes and the
// texture coordinates' derivatives. Particles multiply alpha by a soft radial falloff of the quad
// uv: (1 − r²)² inside the inscribed circle (r = 1 at its edge), 0 outside (only +, −, ×: the
// same bits on every machine). A textured object multiplies the colour by the texel, channel by
// channel in fp32 (a shader's `colour * texture(sampler, uv)`). Inline: every transparent
// fragment calls it. Attribute k at a[k · stride].
// shadeSurfaceReads(object) is how many of the leading attributes it reads for the object, and
// shadeSurfaceDerivatives(object) the first of the two whose derivatives it reads (−1: none):
// a fragment program's attributesRead and derivativesOf.
inline int shadeSurfaceReads(const SceneObject& object) {
  return object.type == ObjectType::Particles || object.texture ? kSceneAttributeCount : 4;
}
inline int shadeSurfaceDerivatives(const SceneObject& object) { return object.texture ? 4 : -1; }
// The vertex colour, attributes 0–3: what shadeSurface gives an untextured mesh.
inline glm::vec4 vertexColour(const float* a, int stride) { return {a[0], a[stride], a[2 * stride], a[3 * stride]}; }
// A particle's alpha at quad uv (u, v): alpha·(1 − r²)² inside the inscribed circle, 0 outside.
// F: one float, or a vector of floats (the lanes of shadeSurfaceBatch), the same operations.
template <typename F>
inline F particleAlpha(F alpha, F u, F v) {
  const F x = 2.0f * u - 1.0f, y = 2.0f * v - 1.0f;
  const F r2 = x * x + y * y, inside = (1.0f - r2) * (1.0f - r2);
  const F falloff = r2 < 1.0f ? inside : F{};
  return alpha * falloff;
}
inline glm::vec4 shadeSurface(const SceneObject& object, const float* a, int stride = 1, const double* derivatives = nullptr,
                              int derivativeStride = 1, TextureFiltering filtering = TextureFiltering::Exact) {
  glm::vec4 c = vertexColour(a, stride);
  if (object.type == ObjectType::Particles) c.a = particleAlpha<float>(c.a, a[4 * stride], a[5 * stride]);
  if (object.texture)
    c = c * sampleSurfaceTexture(object, a[4 * stride], a[5 * stride], derivatives, derivativeStride, filtering);
  return c;
}
// shadeSurface for fragments [0, count) of a batch (attribute k of fragment i at a[k · stride + i],
// derivatives likewise): the object's kind decided once, not per fragment. `uniform`:
// FragmentBatch::uniformAttributes (bit k: attribute k is the same in every fragment).
inline void shadeSurfaceBatch(const SceneObject& object, const float* a, int stride, const double* derivatives,
                              int derivativeStride, TextureFiltering filtering, int count, glm::vec4* out,
                              uint64_t uniform = 0) {
  if (object.type != ObjectType::Particles && !object.texture) {
    if ((uniform & 0xF) == 0xF) {  // a flat-coloured triangle: the colour once
      std::fill_n(out, count, vertexColour(a, stride));
      return;
    }
    for (int i = 0; i < count; ++i) out[i] = vertexColour(a + i, stride);
    return;
  }
  if (object.type == ObjectType::Particles && !object.texture) {
    // The alphas eight at a time in lanes, then the colours (GCC compiled the falloff's
    // comparison into a branch per fragment).
    typedef float v8f __attribute__((vector_size(32)));
    auto row = [&](int k, int i) {
      v8f r;
      std::memcpy(&r, a + size_t(k) * size_t(stride) + size_t(i), sizeof r);
      return r;
    };
    // One colour for the whole batch (its colour attributes uniform): read once, only the alphas vary.
    const bool oneColour = (uniform & 0xF) == 0xF;
    const glm::vec4 colour = vertexColour(a, stride);
    int i = 0;
    for (; i + 8 <= count; i += 8) {
      const v8f alpha = particleAlpha(row(3, i), row(4, i), row(5, i));
      for (int l = 0; l < 8; ++l) {
        out[i + l] = oneColour ? colour : vertexColour(a + i + l, stride);
        out[i + l].a = alpha[l];
      }
    }
    for (; i < count; ++i) out[i] = shadeSurface(object, a + i, stride);
    return;
  }
  for (int i = 0; i < count; ++i)
    out[i] = shadeSurface(object, a + i, stride, derivatives ? derivatives + i : nullptr, derivativeStride, filtering);
}
// The alpha test of an object that has one ("alpha_test"): its fragments whose shaded alpha is
// below the threshold (or NaN) are discarded, as a shader's `if (!(c.a >= threshold)) discard;`.
inline bool surfaceDiscards(const SceneObject& object, const glm::vec4& shaded) {
  return object.alphaTest && !(shaded.a >= *object.alphaTest);
}

}  // namespace oitref
