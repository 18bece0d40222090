// Camera and object transforms (conventions in oitref/oit/scene.h).
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "oitref/oit/scene.h"

namespace oitref {

glm::mat4 Camera::view() const { return glm::lookAt(position, target, up); }

// glm::perspective (right-handed, clip z in [−w, w]), with tan evaluated in double so the
// matrix does not depend on which fp32 tanf a C library ships.
namespace {
std::string shortNumber(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", double(v));
  return text;
}

glm::mat4 perspective(const Camera& c, float aspect) {
  const double halfFov = double(c.fovYDegrees) * 3.14159265358979323846 / 360.0;
  const float f = float(1.0 / std::tan(halfFov));
  glm::mat4 p(0.0f);
  p[0][0] = f / aspect;
  p[1][1] = f;
  p[2][2] = -(c.farPlane + c.nearPlane) / (c.farPlane - c.nearPlane);
  p[2][3] = -1.0f;
  p[3][2] = -(2.0f * c.farPlane * c.nearPlane) / (c.farPlane - c.nearPlane);
  return p;
}
}  // namespace

glm::mat4 Camera::projection(float aspect) const {
  if (const std::string problem = projectionProblem(aspect); !problem.empty()) throw std::invalid_argument("camera: " + problem);
  return perspective(*this, aspect);
}

std::string Camera::projectionProblem(float aspect) const {
  const glm::mat4 p = perspective(*this, aspect);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(p[i][j]))
        return "the perspective projection of fov_y " + shortNumber(fovYDegrees) + ", near " + shortNumber(nearPlane) +
               ", far " + shortNumber(farPlane) + " is not finite in fp32" +
               (std::isfinite(p[1][1]) ? " (2·far·near overflows)" : " (1/tan(fov_y/2) overflows)");
  // The ray cast traces from the camera's position, and Embree refuses coordinates beyond its
  // FLT_LARGE (an assertion inside the library); at that distance fp32 cannot place a scene of
  // ordinary size in view space anyway (an ulp of 1e18 is 1e11).
  for (int k = 0; k < 3; ++k)
    if (!(std::fabs(position[k]) <= kRayCastLargestCoordinate))
      return "position " + shortNumber(position[k]) + " lies beyond ±1.844e18, where the ray cast (Embree) cannot trace from";
  // A denormal entry (near 7e-41 makes the depth term 2·far·near/(far − near) one): GPUs flush
  // fp32 denormals to zero in shaders, which puts every depth on the far plane, and oitref's fp32
  // vertex stage keeps only a few bits of it, so nothing beyond a sliver past the near plane has
  // a depth below 1 (fuzz_camera: the rasterizer drew nothing where the ray cast saw particles).
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (std::fpclassify(p[i][j]) == FP_SUBNORMAL)
        return i == 3 && j == 2 ? "near " + shortNumber(nearPlane) + " is so small that the perspective projection's depth term " +
                                      "2·far·near/(far − near) is denormal in fp32 (GPUs flush it to 0, putting every depth on the far plane)"
                                : "the perspective projection of fov_y " + shortNumber(fovYDegrees) + " at aspect " + shortNumber(aspect) +
                                      " has a denormal entry in fp32 (GPUs flush it to 0)";
  // The ray cast's rays through the view's corners (raycast.cpp, PixelRays): the near plane's
  // point to the far plane's, or to the middle depth's where the far one is at infinity.
  const glm::dmat4 inverse = glm::inverse(glm::dmat4(p) * glm::dmat4(view()));
  auto unproject = [&](double x, double y, double z) {
    const glm::dvec4 e = inverse * glm::dvec4(x, y, z, 1.0);
    return glm::dvec3(e) / e.w;
  };
  auto finite = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  for (const double x : {-1.0, 1.0})
    for (const double y : {-1.0, 1.0}) {
      const glm::dvec3 nearPoint = unproject(x, y, -1.0);
      glm::dvec3 direction = unproject(x, y, 1.0) - nearPoint;
      if (!finite(direction)) direction = unproject(x, y, 0.0) - nearPoint;
      if (!finite(direction))
        return "near " + shortNumber(nearPlane) + " and far " + shortNumber(farPlane) +
               " are too far apart for fp32: the projection puts every depth on the far plane";
    }
  return "";
}

// Composed in double and rounded once, so the sub-ulp differences between C libraries' fp32
// sin/cos do not reach the matrix.
glm::mat4 SceneObject::modelMatrix() const {
  const glm::dvec3 r = glm::radians(glm::dvec3(rotationDegrees));
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(position));
  m = glm::rotate(m, r.z, glm::dvec3(0, 0, 1));
  m = glm::rotate(m, r.y, glm::dvec3(0, 1, 0));
  m = glm::rotate(m, r.x, glm::dvec3(1, 0, 0));
  return glm::mat4(glm::scale(m, glm::dvec3(double(scale))));
}

bool SceneObject::isTransparent() const {
  if (transparentOverride) return *transparentOverride;
  if (type == ObjectType::Particles) return true;  // the soft falloff makes alpha < 1 at the edges
  if (texture) {  // a texel's alpha below 1 makes the surface's below 1 there
    const TextureLevel& base = texture->level(0);
    for (size_t i = 3; i < base.texels.size(); i += 4)
      if (base.texels[i] < 255) return true;
  }
  if (colorOverride) return colorOverride->a < 1.0f;
  for (const glm::vec4& c : mesh.colors)
    if (c.a < 1.0f) return true;
  return false;
}

}  // namespace oitref
