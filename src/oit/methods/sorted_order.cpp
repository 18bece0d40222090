#include "methods/sorted_order.h"

#include <algorithm>

#include <glm/mat4x4.hpp>

namespace oitref::methods {
namespace {

double centroidViewDepth(const glm::mat4& view, glm::dvec3 p) { return -(glm::dmat4(view) * glm::dvec4(p, 1.0)).z; }

}  // namespace

std::vector<SortedTriangle> sortedTriangleOrder(const FrameContext& context, bool byTriangle) {
  const glm::mat4 view = context.scene.camera.view();
  std::vector<SortedTriangle> order;
  for (size_t p = 0; p < context.geometry.parts.size(); ++p) {
    const ScenePart& part = context.geometry.parts[p];
    if (!part.transparent) continue;
    glm::dvec3 objectCentroid(0.0);
    for (const glm::vec3& v : part.positions) objectCentroid += glm::dvec3(v);
    objectCentroid /= double(std::max<size_t>(1, part.positions.size()));
    for (size_t t = 0; t < part.triangleCount(); ++t) {
      glm::dvec3 c(0.0);
      for (int k = 0; k < 3; ++k) c += glm::dvec3(part.positions[part.indices[3 * t + size_t(k)]]);
      order.push_back({p, t, centroidViewDepth(view, byTriangle ? c / 3.0 : objectCentroid)});
    }
  }
  std::stable_sort(order.begin(), order.end(), [](const SortedTriangle& a, const SortedTriangle& b) { return a.depth > b.depth; });
  return order;
}

}  // namespace oitref::methods
