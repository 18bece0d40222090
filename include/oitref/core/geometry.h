// Triangles as the vertex stage hands them to the rasterizer: clip-space positions and any number
// of float attributes per vertex, optionally indexed. Triangle t is vertices (3t, 3t+1, 3t+2),
// or the indices at those positions. Its gl_PrimitiveID is t.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "oitref/core/fp_environment.h"

namespace oitref {

struct Geometry {
  std::vector<glm::vec4> clipPositions;
  int attributeCount = 0;
  std::vector<float> attributes;  // vertexCount × attributeCount, vertex-major
  std::vector<uint32_t> indices;  // empty: non-indexed

  size_t vertexCount() const { return clipPositions.size(); }
  size_t triangleCount() const { return (indices.empty() ? clipPositions.size() : indices.size()) / 3; }
  uint32_t vertexIndex(size_t triangle, int corner) const {
    const size_t i = triangle * 3 + size_t(corner);
    return indices.empty() ? uint32_t(i) : indices[i];
  }
  const float* vertexAttributes(uint32_t vertex) const { return attributes.data() + size_t(vertex) * attributeCount; }

  // Throws std::invalid_argument when sizes disagree or an index is out of range.
  void validate() const;

  // Runs a vertex shader `clip = vs(vertexIndex, float* attributesOut)` over vertexCount vertices,
  // under the default floating-point environment.
  template <typename VertexShader>
  static Geometry fromVertexShader(size_t vertexCount, int attributeCount, VertexShader&& vs) {
    const DefaultFloatingPoint fp;
    Geometry g;
    g.attributeCount = attributeCount;
    g.clipPositions.resize(vertexCount);
    g.attributes.resize(vertexCount * size_t(attributeCount));
    for (size_t v = 0; v < vertexCount; ++v) g.clipPositions[v] = vs(v, g.attributes.data() + v * attributeCount);
    return g;
  }
};

}  // namespace oitref
