// Depth precision: where a camera's near and far lie so far apart that the rasterizer's depth of
// a surface in plain view rounds onto the far plane. The depth test (LESS against the clear, 1.0)
// then fails there and the surface is lost, exactly as on a GPU, while the ray cast, which has no
// depth buffer, sees it: the two ground truths disagree. Whether that happens depends on where
// the geometry lies, not on the camera alone (near 1e-6 with far 1e3 serves a scene at distance
// 0.01 and loses one at distance 100: its window depth 1 − 1e-8 rounds to 1), so the check runs
// over the scene's vertices.
//
// What counts: a point no farther than half the far distance. Every camera loses a sliver just in
// front of its far plane (with near 0.1 and far 50, the last 0.75 mm); that is a GPU's behaviour
// and stays. A surface at half the far distance or nearer is one that anybody who chose the camera
// expects to see.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "oitref/core/depth.h"
#include "oitref/oit/scene_geometry.h"

namespace oitref {
namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

// Whether the window depth of a clip position, as the fragment stage computes it at a vertex
// (fragment_ops.h: ½·z/w + ½ in double from the fp32 clip coordinates), has the D24 code of the
// depth clear (1.0): every method's depth attachment is D24.
bool onFarPlane(const glm::vec4& clip) {
  const double window = 0.5 * double(clip.z) / double(clip.w) + 0.5;
  return encodeDepth(window, DepthFormat::D24) == encodeDepth(1.0, DepthFormat::D24);
}

}  // namespace

std::string depthPrecisionProblem(const SceneGeometry& geometry) {
  const Camera& camera = geometry.camera;
  // The z and w rows of the vertex stage's matrix do not depend on the aspect ratio.
  const glm::mat4 viewProjection = camera.projection(1.0f) * camera.view();
  const glm::dmat4 exactView = glm::lookAt(glm::dvec3(camera.position), glm::dvec3(camera.target), glm::dvec3(camera.up));
  const double nearPlane = camera.nearPlane, halfFar = 0.5 * double(camera.farPlane);
  // A point at half the far distance, through the projection alone: where a triangle spans that
  // distance, this is its point that matters.
  const glm::mat4 projection = camera.projection(1.0f);
  const glm::vec4 halfFarClip = projection * glm::vec4(0.0f, 0.0f, -float(halfFar), 1.0f);
  const bool halfFarLost = onFarPlane(halfFarClip);
  // The exact window depth there is 1 − near·(far − d)/(d·(far − near)).
  const double farPlane = camera.farPlane;
  auto problem = [&](size_t object, double distance) {
    const double belowOne = nearPlane * (farPlane - distance) / (distance * (farPlane - nearPlane));
    return "near " + number(nearPlane) + " and far " + number(farPlane) +
           " leave fp32 depth no precision where objects[" + std::to_string(object) + "] lies: at view distance " +
           number(distance) + " its window depth 1 − " + number(belowOne) +
           " rounds onto the far plane, so the rasterizer would lose it behind the depth clear where the ray cast "
           "sees it; raise near or lower far (at distance d the depth is about 1 − near/d)";
  };
  for (const ScenePart& part : geometry.parts) {
    std::vector<double> distance(part.positions.size());
    for (size_t v = 0; v < part.positions.size(); ++v) {
      const glm::vec3& p = part.positions[v];
      distance[v] = -(exactView * glm::dvec4(glm::dvec3(p), 1.0)).z;
      if (!(distance[v] > nearPlane && distance[v] <= halfFar)) continue;
      if (onFarPlane(viewProjection * glm::vec4(p, 1.0f))) return problem(part.objectIndex, distance[v]);
    }
    if (!halfFarLost || !(halfFar > nearPlane)) continue;
    for (size_t t = 0; t + 2 < part.indices.size(); t += 3) {
      const double a = distance[part.indices[t]], b = distance[part.indices[t + 1]], c = distance[part.indices[t + 2]];
      if (std::min({a, b, c}) <= halfFar && std::max({a, b, c}) > halfFar)
        return problem(part.objectIndex, halfFar);
    }
  }
  return "";
}

}  // namespace oitref
