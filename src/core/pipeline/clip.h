// Stage 1: clipping in homogeneous clip space (GL 4.6 §13.7).
//
// Planes, each as distance(v) ≥ 0:
//   near  z + w ≥ 0 and far  w − z ≥ 0 (both skipped with depth clamp, GL §13.7);
//   guard band |x| ≤ G·w, |y| ≤ G·w with G = kGuardBand, so window coordinates stay within
//   ±2^21 pixels and fixed-point edge functions fit in int64 (setup.h) — samples outside the
//   guard band are never inside a viewport, so this clip changes no coverage;
//   w ≥ kMinW, so the perspective divide never meets w ≤ 0.
// Sutherland–Hodgman in double. An intersection is always computed from the inside vertex
// towards the outside one, so two triangles sharing an edge produce bit-identical new vertices
// (watertightness). Clipping decides coverage only: attributes and depth are interpolated from
// the original triangle (fragment_ops.h), so they do not depend on where it was clipped.
#pragma once

#include <glm/vec4.hpp>

namespace oitref::detail {

inline constexpr double kGuardBand = 128.0;
inline constexpr double kMinW = 1.0 / (1ull << 60);
inline constexpr int kMaxClipVertices = 16;  // 3 + one per plane (7), with room to spare

struct ClipVertex {
  glm::dvec4 position;  // clip space
};

// Clips the triangle; writes the polygon (0 or ≥ 3 vertices, in order) and returns its size.
int clipTriangle(const ClipVertex in[3], bool clipNearFar, ClipVertex out[kMaxClipVertices]);

}  // namespace oitref::detail
