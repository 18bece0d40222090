#include <stdexcept>
#include <string>

#include "oitref/core/geometry.h"

namespace oitref {

void Geometry::validate() const {
  const size_t n = vertexCount();
  if (triangleCount() > (size_t(1) << 28))
    throw std::invalid_argument("geometry: " + std::to_string(triangleCount()) +
                                " triangles in one draw; at most 2^28 are supported");
  if (attributeCount < 0) throw std::invalid_argument("geometry: negative attributeCount");
  if (attributes.size() != n * size_t(attributeCount))
    throw std::invalid_argument("geometry: " + std::to_string(attributes.size()) + " attribute floats for " +
                                std::to_string(n) + " vertices × " + std::to_string(attributeCount) + " attributes");
  if (indices.empty()) {
    if (n % 3 != 0) throw std::invalid_argument("geometry: non-indexed vertex count " + std::to_string(n) +
                                                " is not a multiple of 3");
    return;
  }
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("geometry: index count " + std::to_string(indices.size()) + " is not a multiple of 3");
  for (size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= n)
      throw std::invalid_argument("geometry: index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                                  ", but there are only " + std::to_string(n) + " vertices");
}

}  // namespace oitref
