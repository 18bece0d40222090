#include "pipeline/llvmpipe_setup.h"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace oitref::detail {
namespace {

// Mesa's clipper holds at most 2·(6 + 8) + 1 vertices (draw_pipe_clip.c, MAX_CLIPPED_VERTICES).
constexpr int kMaxDrawVertices = 2 * (6 + 8) + 1;

// A vertex as the draw module hands it on: its clip position (vertex_header::clip_pos), its
// window position and 1/w (the position output after the viewport), its attributes.
struct DrawVertex {
  float clip[4];
  float window[4];
  const float* attributes;
};

struct Viewport {
  float scale[3], translate[3];
};

// _mesa_get_viewport_xform with depth range [0, 1] and GL's clip control (z in [−1, 1]).
Viewport viewportOf(const SetupContext& c) {
  const float halfW = float(c.vw) * 0.5f, halfH = float(c.vh) * 0.5f;
  return {{halfW, halfH, 0.5f}, {halfW + float(c.vx), halfH + float(c.vy), 0.5f}};
}

// draw_llvm.c, generate_clipmask: the view volume's six bits (z's two only when clipping z).
unsigned clipMask(const float* p, bool clipZ) {
  const float x = p[0], y = p[1], z = p[2], w = p[3];
  unsigned m = 0;
  if (x > w) m |= 1u;
  if (0.0f > x + w) m |= 2u;
  if (y > w) m |= 4u;
  if (0.0f > y + w) m |= 8u;
  if (clipZ) {
    if (0.0f > z + w) m |= 16u;
    if (z > w) m |= 32u;
  }
  return m;
}

// draw_llvm.c, generate_viewport: the vertex shader's output through the viewport.
void windowFromShader(DrawVertex& v, const Viewport& vp, bool fused) {
  const float oow = 1.0f / v.clip[3];
  for (int i = 0; i < 3; ++i) {
    const float p = v.clip[i] * oow;
    v.window[i] = fused ? __builtin_fmaf(p, vp.scale[i], vp.translate[i]) : p * vp.scale[i] + vp.translate[i];
  }
  v.window[3] = oow;
}

// draw_pipe_clip.c's planes (draw_context.c, draw->plane[0..5]) and getclipdist's dot4.
constexpr float kPlanes[6][4] = {{-1, 0, 0, 1}, {1, 0, 0, 1}, {0, -1, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {0, 0, -1, 1}};
float planeDistance(const DrawVertex& v, int plane) {
  const float* p = kPlanes[plane];
  return v.clip[0] * p[0] + v.clip[1] * p[1] + v.clip[2] * p[2] + v.clip[3] * p[3];
}

// The clipper's output vertices and their attributes (draw_pipe_clip.c, interp).
struct ClipScratch {
  DrawVertex vertices[kMaxDrawVertices + 1];
  std::vector<float> attributes;
  int used = 0;
};

const DrawVertex* interpolate(ClipScratch& s, int attributeCount, float t, const DrawVertex& out, const DrawVertex& in,
                              const Viewport& vp) {
  DrawVertex& d = s.vertices[s.used];
  float* a = s.attributes.data() + size_t(s.used) * size_t(attributeCount);
  ++s.used;
  for (int i = 0; i < 4; ++i) d.clip[i] = out.clip[i] + t * (in.clip[i] - out.clip[i]);  // LINTERP
  const float oow = 1.0f / d.clip[3];
  for (int i = 0; i < 3; ++i) d.window[i] = d.clip[i] * oow * vp.scale[i] + vp.translate[i];
  d.window[3] = oow;
  for (int k = 0; k < attributeCount; ++k) a[k] = out.attributes[k] + t * (in.attributes[k] - out.attributes[k]);
  d.attributes = a;
  return &d;
}

// lp_state_setup.c, calc_coef4 for the values a0, a1, a2 of the set-up order.
struct PlaneSetup {
  float x0Center, y0Center, dx01, dy01, dx20, dy20;  // the last four times ooa
};

PlaneSetup planeSetupOf(const DrawVertex& v0, const DrawVertex& v1, const DrawVertex& v2) {
  PlaneSetup s;
  s.x0Center = v0.window[0] - 0.5f;
  s.y0Center = v0.window[1] - 0.5f;
  const float dx01 = v0.window[0] - v1.window[0], dy01 = v0.window[1] - v1.window[1];
  const float dx20 = v2.window[0] - v0.window[0], dy20 = v2.window[1] - v0.window[1];
  const float e = dx01 * dy20, f = dy01 * dx20;
  const float ooa = 1.0f / (e - f);
  s.dx01 = dx01 * ooa, s.dy01 = dy01 * ooa, s.dx20 = dx20 * ooa, s.dy20 = dy20 * ooa;
  return s;
}

void planeOf(const PlaneSetup& s, float a0, float a1, float a2, float* out) {
  const float da01 = a0 - a1, da20 = a2 - a0;
  const float dadx = da01 * s.dy20 - da20 * s.dy01;
  const float dady = da20 * s.dx01 - da01 * s.dx20;
  out[0] = a0 - (dadx * s.x0Center + dady * s.y0Center);
  out[1] = dadx;
  out[2] = dady;
}

// lp_setup_tri.c, calc_fixed_position's snap: (x − 0.5)·256 in fp32, to nearest even
// (cvtps2dq, which gives INT32_MIN for NaN and values beyond int32). In oitref's fixed point the
// pixel centre is 256·i + 128, so 128 is added back.
int64_t snap(float window) {
  const float scaled = (window - 0.5f) * 256.0f;
  const int64_t fixed = scaled >= -0x1p31f && scaled < 0x1p31f ? int64_t(std::nearbyint(scaled)) : int64_t(INT32_MIN);
  return fixed + 128;
}

// One triangle as llvmpipe's setup receives it (triangle_both): oriented, culled, its planes.
void emit(const DrawVertex* a, const DrawVertex* b, const DrawVertex* c, uint32_t primitiveId, const uint32_t source[3],
          const SetupContext& context, int attributeCount, std::vector<SetupTriangle>& out, std::vector<float>& planes,
          SetupCounters& counters) {
  const int64_t ax = snap(a->window[0]), ay = snap(a->window[1]);
  const int64_t bx = snap(b->window[0]), by = snap(b->window[1]);
  const int64_t cx = snap(c->window[0]), cy = snap(c->window[1]);
  // A vertex cvtps2dq could not convert (NaN, or beyond int32 after the clipper's rounding):
  // llvmpipe's edge functions would be meaningless there, oitref's would overflow; dropped.
  constexpr int64_t kOut = int64_t(INT32_MIN) + 128;
  if (ax == kOut || ay == kOut || bx == kOut || by == kOut || cx == kOut || cy == kOut) return;
  // llvmpipe's area: (x0 − x1)(y2 − y0) − (x2 − x0)(y0 − y1), positive for GL's clockwise.
  const int64_t area = (ax - bx) * (cy - ay) - (cx - ax) * (ay - by);
  if (area == 0) return;
  const DrawVertex* v[3] = {a, b, c};
  if (area < 0) std::swap(v[0], v[1]);  // retry_triangle_ccw(v1, v0, v2)
  const size_t before = out.size();
  emitSnappedTriangle(ax, ay, bx, by, cx, cy, source, primitiveId, TriangleInterpolation{}, context, out, counters);
  if (out.size() == before) return;
  const PlaneSetup s = planeSetupOf(*v[0], *v[1], *v[2]);
  const size_t base = planes.size();
  planes.resize(base + size_t(llvmpipePlaneFloats(attributeCount)));
  float* p = planes.data() + base;
  planeOf(s, v[0]->window[2], v[1]->window[2], v[2]->window[2], p);
  planeOf(s, v[0]->window[3], v[1]->window[3], v[2]->window[3], p + 3);
  for (int k = 0; k < attributeCount; ++k)  // apply_perspective_corr: a·(1/w) at each vertex
    planeOf(s, v[0]->attributes[k] * v[0]->window[3], v[1]->attributes[k] * v[1]->window[3],
            v[2]->attributes[k] * v[2]->window[3], p + 6 + 3 * k);
}

}  // namespace

void setupPrimitiveLlvmpipe(const Geometry& geometry, size_t t, const SetupContext& context, std::vector<SetupTriangle>& out,
                            std::vector<float>& planes, SetupCounters& counters) {
  const Viewport vp = viewportOf(context);
  const int n = geometry.attributeCount;
  DrawVertex in[3];
  uint32_t source[3];
  glm::vec4 positions[3];
  unsigned masks[3];
  if (!triangleVertices(geometry, t, source, positions, counters)) return;
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 4; ++i) in[k].clip[i] = positions[k][i];
    in[k].attributes = geometry.vertexAttributes(source[k]);
    masks[k] = clipMask(in[k].clip, context.clipNearFar);
    windowFromShader(in[k], vp, context.fusedMultiplyAdd);
  }
  unsigned clip = masks[0] | masks[1] | masks[2];
  if (clip == 0) return emit(&in[0], &in[1], &in[2], uint32_t(t), source, context, n, out, planes, counters);
  if (masks[0] & masks[1] & masks[2]) return;

  // draw_pipe_clip.c, do_clip_tri.
  thread_local ClipScratch scratch;
  scratch.used = 0;
  scratch.attributes.resize(size_t(kMaxDrawVertices + 1) * size_t(n));
  const DrawVertex* listA[kMaxDrawVertices + 1] = {&in[0], &in[1], &in[2]};
  const DrawVertex* listB[kMaxDrawVertices + 1];
  const DrawVertex** inList = listA;
  const DrawVertex** outList = listB;
  int count = 3;
  while (clip && count >= 3) {
    const int plane = __builtin_ctz(clip);
    clip &= clip - 1;
    const DrawVertex* previous = inList[0];
    float dPrevious = planeDistance(*previous, plane);
    if (!std::isfinite(dPrevious)) return;
    inList[count] = inList[0];
    int outCount = 0;
    for (int i = 1; i <= count; ++i) {
      const DrawVertex* vertex = inList[i];
      const float d = planeDistance(*vertex, plane);
      if (!std::isfinite(d)) return;
      bool differentSign;
      if (dPrevious >= 0.0f) {
        if (outCount >= kMaxDrawVertices) return;
        outList[outCount++] = previous;
        differentSign = d < 0.0f;
      } else {
        differentSign = !(d < 0.0f);
      }
      if (differentSign) {
        if (outCount >= kMaxDrawVertices || scratch.used > kMaxDrawVertices) return;
        const float denom = d - dPrevious;
        const DrawVertex* made;
        if (d < 0.0f)  // going out
          made = -d < dPrevious ? interpolate(scratch, n, d / denom, *vertex, *previous, vp)
                                : interpolate(scratch, n, -dPrevious / denom, *previous, *vertex, vp);
        else  // coming back in
          made = -dPrevious < d ? interpolate(scratch, n, -dPrevious / denom, *previous, *vertex, vp)
                                : interpolate(scratch, n, d / denom, *vertex, *previous, vp);
        outList[outCount++] = made;
      }
      previous = vertex;
      dPrevious = d;
    }
    std::swap(inList, outList);
    count = outCount;
  }
  // emit_poly with the last vertex provoking: (v[i−1], v[i], v[0]).
  for (int i = 2; i < count; ++i)
    emit(inList[i - 1], inList[i], inList[0], uint32_t(t), source, context, n, out, planes, counters);
}

}  // namespace oitref::detail
