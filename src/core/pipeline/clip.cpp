#include "pipeline/clip.h"

#include <utility>

namespace oitref::detail {
namespace {

constexpr int kPlaneCount = 7;

double planeDistance(int plane, const glm::dvec4& v) {
  switch (plane) {
    case 0: return v.z + v.w;                // near
    case 1: return v.w - v.z;                // far
    case 2: return kGuardBand * v.w - v.x;   // right guard band
    case 3: return kGuardBand * v.w + v.x;   // left
    case 4: return kGuardBand * v.w - v.y;   // top
    case 5: return kGuardBand * v.w + v.y;   // bottom
    default: return v.w - kMinW;             // w > 0
  }
}

ClipVertex intersect(const ClipVertex& in, double dIn, const ClipVertex& out, double dOut) {
  const double t = dIn / (dIn - dOut);
  return {in.position + t * (out.position - in.position)};
}

}  // namespace

int clipTriangle(const ClipVertex in[3], bool clipNearFar, ClipVertex out[kMaxClipVertices]) {
  // Fast paths: entirely inside every plane, or entirely outside one.
  unsigned outside[3] = {0, 0, 0};
  for (int p = clipNearFar ? 0 : 2; p < kPlaneCount; ++p)
    for (int i = 0; i < 3; ++i)
      if (!(planeDistance(p, in[i].position) >= 0.0)) outside[i] |= 1u << p;
  if ((outside[0] | outside[1] | outside[2]) == 0) {
    for (int i = 0; i < 3; ++i) out[i] = in[i];
    return 3;
  }
  if (outside[0] & outside[1] & outside[2]) return 0;

  ClipVertex bufferA[kMaxClipVertices], bufferB[kMaxClipVertices];
  ClipVertex* src = bufferA;
  ClipVertex* dst = bufferB;
  int count = 3;
  for (int i = 0; i < 3; ++i) src[i] = in[i];
  for (int p = clipNearFar ? 0 : 2; p < kPlaneCount && count > 0; ++p) {
    if (((outside[0] | outside[1] | outside[2]) & (1u << p)) == 0) continue;
    int n = 0;
    for (int i = 0; i < count; ++i) {
      const ClipVertex& a = src[i];
      const ClipVertex& b = src[(i + 1) % count];
      const double da = planeDistance(p, a.position), db = planeDistance(p, b.position);
      const bool aIn = da >= 0.0, bIn = db >= 0.0;
      if (aIn) dst[n++] = a;
      if (aIn != bIn && n < kMaxClipVertices) dst[n++] = aIn ? intersect(a, da, b, db) : intersect(b, db, a, da);
    }
    count = n < 3 ? 0 : n;
    std::swap(src, dst);
  }
  for (int i = 0; i < count; ++i) out[i] = src[i];
  return count;
}

}  // namespace oitref::detail
