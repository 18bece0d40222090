#include "pipeline/setup.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace oitref::detail {
namespace {

struct WindowVertex {
  int64_t x, y;  // fixed point, S units per pixel
};

WindowVertex toWindow(const ClipVertex& v, const SetupContext& c) {
  const double scale = double(int64_t(1) << c.raster.subpixelBits);
  const glm::dvec4& p = v.position;
  // The clipper keeps |x|, |y| ≤ G·w, but an intersection on an edge whose ends lie 1e30 apart
  // can land outside by its own rounding (fuzz_camera: a window x of 9.7e25, beyond int64 once
  // snapped). The clamp puts such a point back on the guard band; every point the clipper places
  // inside is unchanged.
  const double xNdc = std::clamp(p.x / p.w, -kGuardBand, kGuardBand), yNdc = std::clamp(p.y / p.w, -kGuardBand, kGuardBand);
  const double halfW = 0.5 * c.vw, halfH = 0.5 * c.vh;
  const double xw = xNdc * halfW + (c.vx + halfW);
  const double yw = yNdc * halfH + (c.vy + halfH);
  WindowVertex out;
  out.x = int64_t(std::nearbyint(xw * scale));  // ties to even (default FP environment)
  out.y = int64_t(std::nearbyint(yw * scale));
  return out;
}

// A vertex's clip position moved to where the rasteriser snapped it (window position `snapped`),
// keeping its z and w: raster=nvidia interpolates from these (setupPrimitive).
glm::dvec4 atSnappedPosition(const glm::dvec4& p, WindowVertex snapped, const SetupContext& c) {
  const double scale = double(int64_t(1) << c.raster.subpixelBits);
  const double halfW = 0.5 * c.vw, halfH = 0.5 * c.vh;
  return {(double(snapped.x) / scale - (c.vx + halfW)) / halfW * p.w, (double(snapped.y) / scale - (c.vy + halfH)) / halfH * p.w,
          p.z, p.w};
}

bool isInclusive(int64_t dx, int64_t dy, FillConvention fill) {
  if (dy < 0) return true;  // left edge (counter-clockwise, y up: walking downwards)
  if (dy != 0) return false;
  return fill == FillConvention::TopLeft ? dx < 0 : dx > 0;  // top edge walks left, bottom edge right
}

}  // namespace

void emitSnappedTriangle(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx, int64_t cy, const uint32_t source[3],
                         uint32_t primitiveId, const TriangleInterpolation& interpolation, const SetupContext& c,
                         std::vector<SetupTriangle>& out, SetupCounters& counters) {
  const WindowVertex w0{ax, ay}, w1{bx, by}, w2{cx, cy};
  const WindowVertex *v0 = &w0, *v1 = &w1, *v2 = &w2;
  int64_t area2 = (v1->x - v0->x) * (v2->y - v0->y) - (v2->x - v0->x) * (v1->y - v0->y);
  if (area2 == 0) return;
  const bool counterClockwise = area2 > 0;
  const bool front = counterClockwise == (c.raster.frontFace == FrontFace::CounterClockwise);
  if ((c.raster.cull == CullMode::Back && !front) || (c.raster.cull == CullMode::Front && front)) return;
  if (!counterClockwise) {
    std::swap(v1, v2);
    area2 = -area2;
  }
  const WindowVertex* v[3] = {v0, v1, v2};

  SetupTriangle t;
  const int64_t S = int64_t(1) << c.raster.subpixelBits;
  int64_t minX = v0->x, maxX = v0->x, minY = v0->y, maxY = v0->y;
  for (int i = 0; i < 3; ++i) {
    const WindowVertex& a = *v[(i + 1) % 3];
    const WindowVertex& b = *v[(i + 2) % 3];
    t.edgeA[i] = -(b.y - a.y);
    t.edgeB[i] = b.x - a.x;
    t.edgeC[i] = -(t.edgeA[i] * a.x + t.edgeB[i] * a.y);
    minX = std::min(minX, v[i]->x), maxX = std::max(maxX, v[i]->x);
    minY = std::min(minY, v[i]->y), maxY = std::max(maxY, v[i]->y);
  }
  t.inclusiveEdges = 0;
  for (int i = 0; i < 3; ++i)
    if (isInclusive(t.edgeB[i], -t.edgeA[i], c.raster.fill)) t.inclusiveEdges |= uint8_t(1u << i);

  // Pixels whose centre x·S + S/2 lies in [minX, maxX], intersected with the viewport.
  const int64_t x0 = std::max<int64_t>(c.vx, -floorDiv(-(minX - S / 2), S));
  const int64_t x1 = std::min<int64_t>(c.vx + c.vw, floorDiv(maxX - S / 2, S) + 1);
  const int64_t y0 = std::max<int64_t>(c.vy, -floorDiv(-(minY - S / 2), S));
  const int64_t y1 = std::min<int64_t>(c.vy + c.vh, floorDiv(maxY - S / 2, S) + 1);
  if (x0 >= x1 || y0 >= y1) return;
  t.bounds = {int(x0), int(y0), int(x1), int(y1)};

  t.interpolation = interpolation;
  t.primitiveId = primitiveId;
  t.frontFacing = front;
  for (int k = 0; k < 3; ++k) t.vertexIndex[k] = source[k];
  out.push_back(t);
  ++counters.rasterized;
}

bool triangleVertices(const Geometry& geometry, size_t t, uint32_t source[3], glm::vec4 positions[3], SetupCounters& counters) {
  for (int k = 0; k < 3; ++k) {
    source[k] = geometry.vertexIndex(t, k);
    const glm::vec4& p = geometry.clipPositions[source[k]];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w)) {
      ++counters.nonFinite;
      return false;
    }
    positions[k] = p;
  }
  return true;
}

void setupPrimitive(const Geometry& geometry, size_t t, const SetupContext& context,
                    std::vector<SetupTriangle>& out, SetupCounters& counters) {
  ClipVertex in[3];
  uint32_t source[3];
  glm::vec4 positions[3];
  if (!triangleVertices(geometry, t, source, positions, counters)) return;
  for (int k = 0; k < 3; ++k) in[k].position = glm::dvec4(positions[k]);
  ClipVertex polygon[kMaxClipVertices];
  const int n = clipTriangle(in, context.clipNearFar, polygon);
  if (n < 3) return;
  // A vertex that clipping made is a few roundings of coordinates as large as the triangle's, so
  // off by up to ~8·M·2^−53 in each; divided by its w and scaled to the viewport, that is how far
  // it may be from where the exact intersection lies. Far beyond the guard band (clip
  // coordinates of 1e32 where the viewport spans 384, from a camera zoomed to fov_y 1e-30) that is
  // more than the whole viewport: such a draw is refused (drawSequence), not drawn from rounding.
  double m = -1.0;  // computed for the first vertex that clipping made
  for (int i = 0; i < n; ++i) {
    const glm::dvec4& p = polygon[i].position;
    if (p == in[0].position || p == in[1].position || p == in[2].position) continue;  // an original vertex: exact
    if (m < 0.0)
      for (const ClipVertex& v : in)
        m = std::max({m, std::fabs(v.position.x), std::fabs(v.position.y), std::fabs(v.position.z), std::fabs(v.position.w)});
    const double ndcError = 8.0 * m * 0x1p-53 * (1.0 + kGuardBand) / p.w;
    counters.clipErrorPixels = std::max(counters.clipErrorPixels, ndcError * 0.5 * std::max(context.vw, context.vh));
  }
  WindowVertex w[kMaxClipVertices];
  for (int i = 0; i < n; ++i) w[i] = toWindow(polygon[i], context);
  glm::dvec4 clip[3] = {in[0].position, in[1].position, in[2].position};
  // raster=nvidia: a triangle that no clip plane cuts (the clipper returns its three vertices, in
  // order) is interpolated from its vertices where the rasteriser snapped them. Measured on an
  // H200 (docs/nvidia.md): interpolating from the unsnapped vertices differs by up to 1.2e-3 in
  // depth on triangles whose vertices snapping moves; this, by rounding (9.2e-7). Triangles a
  // plane cuts fit neither, and keep Exact's interpolation.
  const bool whole = n == 3 && polygon[0].position == in[0].position && polygon[1].position == in[1].position &&
                     polygon[2].position == in[2].position;
  if (context.rule == Rasterization::Nvidia && whole)
    for (int k = 0; k < 3; ++k) clip[k] = atSnappedPosition(in[k].position, w[k], context);
  const TriangleInterpolation interpolation = interpolationOf(clip);
  for (int i = 1; i + 1 < n; ++i)
    emitSnappedTriangle(w[0].x, w[0].y, w[i].x, w[i].y, w[i + 1].x, w[i + 1].y, source, uint32_t(t), interpolation, context,
                        out, counters);
}

TriangleInterpolation interpolationOf(const glm::dvec4 v[3]) {
  TriangleInterpolation r;
  // M has columns (x_i, y_i, w_i); M⁻¹ = adj(M) / det(M).
  const double m[3][3] = {{v[0].x, v[1].x, v[2].x}, {v[0].y, v[1].y, v[2].y}, {v[0].w, v[1].w, v[2].w}};
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1], c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2],
               c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  r.degenerate = det == 0.0;
  if (!r.degenerate) {
    const double k = 1.0 / det;
    double(&inv)[3][3] = r.inverse;
    inv[0][0] = c00 * k, inv[1][0] = c01 * k, inv[2][0] = c02 * k;
    inv[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * k;
    inv[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * k;
    inv[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * k;
    inv[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * k;
    inv[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * k;
    inv[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * k;
  }
  for (int i = 0; i < 3; ++i) r.clipZ[i] = v[i].z;
  return r;
}

}  // namespace oitref::detail
