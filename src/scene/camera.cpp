// Camera and object transforms (conventions in oitref/scene.h).
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "oitref/scene.h"

namespace oitref {

glm::mat4 Camera::view() const { return glm::lookAt(position, target, up); }

// glm::perspective (right-handed, clip z in [−w, w]), with tan evaluated in double so the
// matrix does not depend on which fp32 tanf a C library ships.
glm::mat4 Camera::projection(float aspect) const {
  const double halfFov = double(fovYDegrees) * 3.14159265358979323846 / 360.0;
  const float f = float(1.0 / std::tan(halfFov));
  glm::mat4 p(0.0f);
  p[0][0] = f / aspect;
  p[1][1] = f;
  p[2][2] = -(farPlane + nearPlane) / (farPlane - nearPlane);
  p[2][3] = -1.0f;
  p[3][2] = -(2.0f * farPlane * nearPlane) / (farPlane - nearPlane);
  return p;
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
