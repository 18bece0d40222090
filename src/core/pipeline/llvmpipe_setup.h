// Stages 1–2 under the profile's raster=llvmpipe: clipping, the viewport transform, snapping and
// the interpolation set-up as Mesa 22.3.6's llvmpipe computes them, all in fp32. Each rule names
// the Mesa file and function it follows (docs/rules.md, "raster=llvmpipe").
//
//  * Clip test (draw/draw_llvm.c, generate_clipmask): bit 0 x > w, 1 0 > x + w, 2 y > w,
//    3 0 > y + w, 4 0 > z + w, 5 z > w, each sum rounded to fp32. A triangle whose vertices share
//    a bit is dropped; one with none set is not clipped.
//  * Viewport (draw_llvm.c, generate_viewport): 1/w by division, then x·(1/w)·scale + translate
//    with llvm.fmuladd, which is fused on CPUs with FMA (the profile's fma); scale = (w/2, h/2,
//    ½), translate = (x + w/2, y + h/2, ½). The window vertex keeps 1/w as its fourth value.
//  * Clipping (draw/draw_pipe_clip.c, do_clip_tri): Sutherland–Hodgman in clip space over the
//    planes of the triangle's bits in bit order, the distance dot4(position, plane) in fp32; a new
//    vertex is out + t·(in − out) with t from the vertex inside towards the one outside the
//    plane as the file orders it, and its window position is ((x·(1/w))·scale) + translate
//    (interp(): C, no fused multiply-add); attributes are interpolated with t in clip space.
//    The polygon is emitted as the fan (v[i−1], v[i], v[0]) (emit_poly, last provoking vertex).
//  * Snapping (llvmpipe/lp_setup_tri.c, calc_fixed_position): X = round-to-nearest-even of
//    (x − 0.5)·256 in fp32; the pixel centre of column i is X = 256·i. A triangle with zero
//    fixed-point area is dropped; one of negative area (llvmpipe's orientation, clockwise in GL's
//    window space) is set up from (v1, v0, v2) instead (triangle_both, retry_triangle_ccw).
//  * Fill rule (lp_setup_tri.c, do_triangle_ccw with bottom_edge_rule 0; a GL framebuffer object
//    keeps y up, st_atom_rasterizer.c): left edges and bottom edges are inside (BottomLeft).
//  * Plane equations (llvmpipe/lp_state_setup.c, init_args and calc_coef4), from the set-up order
//    v0, v1, v2 and their window (x, y, z, 1/w):
//      dx01 = x0 − x1, dy01 = y0 − y1, dx20 = x2 − x0, dy20 = y2 − y0,
//      ooa = 1 / (dx01·dy20 − dy01·dx20), each of dx, dy times ooa;
//      for values a0, a1, a2: da01 = a0 − a1, da20 = a2 − a0,
//        dadx = da01·dy20·ooa − da20·dy01·ooa, dady = da20·dx01·ooa − da01·dx20·ooa,
//        a(0, 0) = a0 − (dadx·(x0 − ½) + dady·(y0 − ½)),
//    each operation rounded to fp32, none fused. Depth is z's plane, 1/w is w's plane, and each
//    (perspective) attribute's plane is of a_i·(1/w_i) (apply_perspective_corr).
//  * Fragments (llvmpipe/lp_bld_interp.c, attribs_update_simple) at pixel (x, y) (integers):
//    v = fma(dady, y, fma(dadx, x, a(0, 0))) (llvm.fmuladd), z + 0 for the polygon offset,
//    gl_FragCoord.w = the 1/w plane's value, an attribute = its plane's value · (1 / that).
#pragma once

#include <cstdint>
#include <vector>

#include "oitref/core/geometry.h"
#include "pipeline/setup.h"

namespace oitref::detail {

// The floats a set-up triangle keeps for its fragments: (a(0, 0), dadx, dady) for window z, for
// 1/w, then for each attribute.
inline int llvmpipePlaneFloats(int attributeCount) { return 3 * (2 + attributeCount); }

// setupPrimitive under raster=llvmpipe: appends 0 or more triangles to `out` and, for each, its
// llvmpipePlaneFloats(geometry.attributeCount) floats to `planes`.
void setupPrimitiveLlvmpipe(const Geometry& geometry, size_t t, const SetupContext& context, std::vector<SetupTriangle>& out,
                            std::vector<float>& planes, SetupCounters& counters);

// One plane's value at pixel (x, y): fma(dady, y, fma(dadx, x, a0)), or the two products and
// sums rounded apart where `fused` is false (a CPU without FMA).
inline float llvmpipePlaneAt(const float* plane, float x, float y, bool fused) {
  if (fused) return __builtin_fmaf(plane[2], y, __builtin_fmaf(plane[1], x, plane[0]));
  return plane[0] + plane[1] * x + plane[2] * y;
}

}  // namespace oitref::detail
