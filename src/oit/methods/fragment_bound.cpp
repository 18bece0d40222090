// The bound counts, for each transparent triangle that certainly yields all its fragments, the
// pixel centres that lie inside it by a margin. Certainly, because the triangle
//  * lies wholly inside the view volume (every vertex with w > 0 and −w < z < w, so no clipping),
//  * lies wholly in front of every opaque triangle (its largest window depth is below the smallest
//    of any opaque vertex, an opaque triangle cut by the near plane counting as depth 0), so the
//    LESS test against the opaque depth passes wherever it is drawn, and
//  * belongs to an object without an alpha test (no fragment is discarded);
// and a pixel centre at least 1/64 pixel inside each of its edges is covered whatever the fill
// rule, the 8-bit sub-pixel snapping (which moves an edge by under 1/256 pixel) or the rounding
// of the double arithmetic here. Culling is off in the transparent passes, so either winding
// counts. Every other triangle adds nothing, which keeps the sum a lower bound.
#include "methods/fragment_bound.h"

#include <algorithm>
#include <cmath>

namespace oitref::methods {
namespace {

struct WindowVertex {
  double x, y, depth;
  bool inside;  // w > 0 and −w < z < w
};

WindowVertex toWindow(const glm::mat4& viewProjection, const glm::vec3& p, int width, int height) {
  const glm::vec4 c = viewProjection * glm::vec4(p, 1.0f);
  const double w = c.w;
  if (!(w > 0.0)) return {0, 0, 0, false};
  // The depth clamped to [0, 1]: where the triangle is cut by the near or far plane, the cut's
  // depth (0 or 1).
  return {(double(c.x) / w + 1.0) * 0.5 * width, (double(c.y) / w + 1.0) * 0.5 * height,
          std::clamp((double(c.z) / w + 1.0) * 0.5, 0.0, 1.0), -w < double(c.z) && double(c.z) < w};
}

// Pixel centres at least `margin` inside the triangle (a, b, c), in the viewport.
uint64_t centresInside(const WindowVertex& a, const WindowVertex& b, const WindowVertex& c, int width, int height) {
  constexpr double kMargin = 1.0 / 64.0;
  const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
  if (!(std::fabs(area) > 0.0)) return 0;
  const double sign = area > 0 ? 1.0 : -1.0;
  // Edge i: nx·x + ny·y + k ≥ margin·|n| inside (normals pointing in).
  const WindowVertex* v[3] = {&a, &b, &c};
  double nx[3], ny[3], k[3];
  for (int i = 0; i < 3; ++i) {
    const WindowVertex& p = *v[i];
    const WindowVertex& q = *v[(i + 1) % 3];
    nx[i] = -(q.y - p.y) * sign, ny[i] = (q.x - p.x) * sign;
    k[i] = -(nx[i] * p.x + ny[i] * p.y) - kMargin * std::hypot(nx[i], ny[i]);
  }
  const double top = std::max({a.y, b.y, c.y}), bottom = std::min({a.y, b.y, c.y});
  const int firstRow = int(std::clamp(std::ceil(bottom - 0.5), 0.0, double(height)));
  const int lastRow = int(std::clamp(std::floor(top - 0.5), -1.0, double(height - 1)));
  uint64_t count = 0;
  for (int row = firstRow; row <= lastRow; ++row) {
    const double y = row + 0.5;
    double lo = 0.5, hi = width - 0.5;  // centres x + 0.5 for x in [0, width)
    bool empty = false;
    for (int i = 0; i < 3 && !empty; ++i) {
      const double rest = ny[i] * y + k[i];  // nx·x + rest ≥ 0
      if (nx[i] > 0) lo = std::max(lo, -rest / nx[i]);
      else if (nx[i] < 0) hi = std::min(hi, -rest / nx[i]);
      else empty = rest < 0;
    }
    if (empty || !(hi >= lo)) continue;
    const double first = std::ceil(lo - 0.5), last = std::floor(hi - 0.5);  // x with lo ≤ x + 0.5 ≤ hi
    if (last >= first) count += uint64_t(last - first + 1);
  }
  return count;
}

}  // namespace

uint64_t transparentFragmentsAtLeast(const SceneGeometry& geometry, int width, int height) {
  const glm::mat4 viewProjection = geometry.camera.projection(float(width) / float(height)) * geometry.camera.view();
  double opaqueNearest = 1.0;
  for (const ScenePart& part : geometry.parts) {
    if (part.transparent) continue;
    for (const glm::vec3& p : part.positions) {
      const WindowVertex v = toWindow(viewProjection, p, width, height);
      opaqueNearest = std::min(opaqueNearest, v.depth);  // behind the eye (w ≤ 0): cut at the near plane, 0
    }
  }
  // A transparent depth this far below the opaque one stays below it through the interpolation's
  // rounding and the depth format's conversion.
  const double frontOfOpaque = opaqueNearest - 1e-5;
  uint64_t total = 0;
  for (const ScenePart& part : geometry.parts) {
    if (!part.transparent || part.alphaTested) continue;
    std::vector<WindowVertex> window(part.positions.size());
    for (size_t i = 0; i < window.size(); ++i) window[i] = toWindow(viewProjection, part.positions[i], width, height);
    for (size_t t = 0; t < part.triangleCount(); ++t) {
      const WindowVertex& a = window[part.indices[3 * t]];
      const WindowVertex& b = window[part.indices[3 * t + 1]];
      const WindowVertex& c = window[part.indices[3 * t + 2]];
      if (!(a.inside && b.inside && c.inside) || std::max({a.depth, b.depth, c.depth}) >= frontOfOpaque) continue;
      total += centresInside(a, b, c, width, height);
    }
  }
  return total;
}

}  // namespace oitref::methods
