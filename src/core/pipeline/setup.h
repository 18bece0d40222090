// Stage 2: triangle setup — perspective divide, viewport transform, snapping, edge functions,
// facing and culling (GL 4.6 §13.8, §14.6).
//
// Numeric layout:
//  * Window coordinates are computed in double: x_w = x_ndc·(w/2) + (x + w/2), and likewise y;
//    z_w = ½·z_ndc + ½ (depth range [0,1], GL §13.8.1).
//  * x_w, y_w are snapped to fixed point with S = 2^subpixelBits units per pixel, rounding to
//    nearest, ties to even. After guard-band clipping |X|, |Y| < 2^30.
//  * Edge i runs from vertex i+1 to vertex i+2 (mod 3): E_i(P) = A_i·P.x + B_i·P.y + C_i with
//    A_i = −(y_b − y_a), B_i = x_b − x_a, C_i = −(A_i·x_a + B_i·y_a); all int64 (|E| < 2^62).
//    P is a pixel centre in the same units: (x·S + S/2, y·S + S/2).
//  * Triangles are reoriented counter-clockwise (in GL's y-up window space) so that E_i > 0
//    inside.
//  * A sample with E_i = 0 belongs to the triangle only if edge i is "top/left" under the fill
//    convention (pipeline_state.h); otherwise the test is E_i > 0.
//  * Facing: the sign of the snapped window-space area (GL §14.6.1 eq. 14.8); counter-clockwise
//    is front with FrontFace::CounterClockwise. Zero-area triangles produce no fragments.
#pragma once

#include <cstdint>
#include <vector>

#include "oitref/core/geometry.h"
#include "oitref/core/pipeline_state.h"
#include "pipeline/clip.h"

namespace oitref::detail {

// ⌊a / b⌋ and ⌈a / b⌉ for b > 0 (C++ division truncates toward zero): pixel bounds at setup,
// covered runs in the rasterizer.
inline int64_t floorDiv(int64_t a, int64_t b) {
  const int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}
inline int64_t ceilDiv(int64_t a, int64_t b) { return -floorDiv(-a, b); }

struct PixelRect {
  int x0, y0, x1, y1;  // inclusive-exclusive: [x0, x1) × [y0, y1)
};

// What interpolation needs of the original triangle (fragment_ops.h): M⁻¹ of the matrix whose
// columns are its vertices' clip (x, y, w), and their clip z. Computed once per triangle here,
// where its vertices are read in order, not in each tile it touches.
struct TriangleInterpolation {
  double inverse[3][3] = {};
  double clipZ[3] = {};
  bool degenerate = false;  // det M = 0: the triangle is seen edge-on and produces no fragments
};
TriangleInterpolation interpolationOf(const glm::dvec4 clip[3]);

// What rasterization needs of one (possibly clipped) triangle. Interpolation goes back to the
// original triangle through vertexIndex.
struct SetupTriangle {
  TriangleInterpolation interpolation;
  int64_t edgeA[3], edgeB[3], edgeC[3];
  PixelRect bounds;         // covered pixel range, clipped to the viewport
  uint32_t primitiveId;
  uint32_t vertexIndex[3];  // vertices of the original triangle, in submission order
  uint8_t inclusiveEdges;   // bit i: samples exactly on edge i are inside
  bool frontFacing;
};

struct SetupContext {
  RasterState raster;
  bool clipNearFar = true;
  // The profile's raster rule (profile.h): Llvmpipe sets up through setupPrimitiveLlvmpipe
  // (llvmpipe_setup.h), with llvm.fmuladd fused where fusedMultiplyAdd.
  Rasterization rule = Rasterization::Exact;
  bool fusedMultiplyAdd = false;
  // Viewport in pixels.
  int vx = 0, vy = 0, vw = 0, vh = 0;
};

struct SetupCounters {
  uint64_t rasterized = 0, nonFinite = 0;
  // The largest distance, in pixels, by which rounding may have moved a vertex that clipping made
  // (a bound: 0 where no triangle was clipped). Renderer::drawSequence refuses a draw where it
  // exceeds a sub-pixel step.
  double clipErrorPixels = 0;
};

// Triangle t's vertex indices and clip positions; false (and counted) where a coordinate is not
// finite: the triangle is dropped (GL leaves the result undefined).
bool triangleVertices(const Geometry& geometry, size_t t, uint32_t source[3], glm::vec4 positions[3], SetupCounters& counters);

// Assembles, clips and sets up triangle `t` of `geometry`, appending 0 or more SetupTriangles.
void setupPrimitive(const Geometry& geometry, size_t t, const SetupContext& context,
                    std::vector<SetupTriangle>& out, SetupCounters& counters);

// The part of set-up after snapping, shared by both rules: the triangle with fixed-point vertices
// a, b, c in S units per pixel (pixel centres at x·S + S/2) is culled or oriented, gets its
// edges, fill rule and pixel bounds, and is appended to `out` unless it has no area or pixels.
void emitSnappedTriangle(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx, int64_t cy, const uint32_t source[3],
                         uint32_t primitiveId, const TriangleInterpolation& interpolation, const SetupContext& context,
                         std::vector<SetupTriangle>& out, SetupCounters& counters);

}  // namespace oitref::detail
