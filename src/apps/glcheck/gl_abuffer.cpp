// The A-buffer's GL version (methods/abuffer.cpp), as GPU A-buffers keep it: per-pixel linked
// lists in shader storage, then a full-screen resolve that composites each list in depth order.
//
// The lists arrive in whatever order the GPU runs fragments, so each node keeps its fragment's
// place in the submission order (part, gl_PrimitiveID) and ties of depth fall back on it: the
// order of methods/depth_order.h (view depth, window depth, submission order), whatever the
// arrival. The composite is OVER back to front in fp32 (precision=float).
//
// Two facts of llvmpipe 22.3.6 shape the resolve:
// - It ends every loop of a shader invocation once all of its loops together have run
//   LP_MAX_TGSI_LOOP_ITERATIONS = 65535 times (gallivm/lp_bld_limits.h, lp_exec_endloop in
//   lp_bld_ir_common.c); past that, the lists would be cut short without a word. The resolve needs
//   about (n/2 + 1)(n + 1) iterations for a list of n nodes, so abuffer() refuses frames whose
//   deepest pixel could need more.
// - Written as two nested loops (for each layer, walk the list), the resolve composited only one
//   layer in whole 8-pixel vectors along the frame's diagonal in every scene, however the loops
//   were bounded. As one loop it matches oitref in every pixel (docs/llvmpipe_frames.md).
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "glcheck/gl_methods.h"
#include "methods/method_common.h"
#include "oitref/core/renderer.h"

namespace oitref::glcheck {
namespace {

constexpr uint64_t kLoopIterations = 65535;  // LP_MAX_TGSI_LOOP_ITERATIONS

// The resolve's loop iterations for a list of n nodes: each pass walks the list (n + 1 steps,
// the last at its end) and composites the two farthest layers in front of the last one.
uint64_t resolveIterations(uint64_t n) { return (n / 2 + 1) * (n + 1); }

struct FragmentCounts {
  uint64_t total = 0;  // every transparent fragment of the frame: the node buffer's capacity
  uint32_t deepest = 0;
  int deepestX = 0, deepestY = 0;
};

// Counted by oitref over the same clip-space triangles, with no depth test: at least what the
// storing pass keeps (it keeps those in front of the opaque depth).
FragmentCounts countTransparentFragments(const FrameContext& frame) {
  const glm::mat4 vp = frame.viewProjection();
  DepthBuffer depth(DepthFormat::D32F, frame.width, frame.height);
  Framebuffer fb;
  fb.depth = &depth;
  PipelineState st;
  st.profile = frame.profile;
  // A pixel's fragments are shaded by one worker, so the per-pixel counts need no atomics.
  std::vector<uint32_t> perPixel(size_t(frame.width) * size_t(frame.height), 0);
  const FragmentProgram count = programOf([&](const FragmentInput& in, FragmentOutput&) {
    ++perPixel[size_t(in.y) * size_t(frame.width) + size_t(in.x)];
  });
  FragmentCounts c;
  for (const ScenePart& part : frame.geometry.parts)
    if (part.transparent) c.total += frame.renderer.draw(fb, st, toClipGeometry(part, vp), count).fragmentsRasterized;
  const auto deepest = std::max_element(perPixel.begin(), perPixel.end());
  c.deepest = *deepest;
  c.deepestX = int(size_t(deepest - perPixel.begin()) % size_t(frame.width));
  c.deepestY = int(size_t(deepest - perPixel.begin()) / size_t(frame.width));
  return c;
}

const char* kStorage = R"(
struct Node {
  vec4 colour;
  float viewDepth, windowDepth;
  uint part, primitive, next;
};
layout(std430, binding = 0) buffer Heads { uint heads[]; };
layout(std430, binding = 1) buffer Nodes { Node nodes[]; };
layout(std430, binding = 2) buffer Counter { uint used; uint capacity; };
const uint NONE = 0xffffffffu;
uint pixelIndex() { return uint(gl_FragCoord.y) * WIDTH + uint(gl_FragCoord.x); }
)";

// Stores every fragment in front of the opaque depth (tested early: the shader has effects).
const char* kStore = R"(
layout(early_fragment_tests) in;
uniform int partIndex;
void main() {
  if (gl_HelperInvocation) return;
  vec4 c = shadeSurface();
  uint n = atomicAdd(used, 1u);
  if (n >= capacity) return;
  nodes[n].colour = c;
  nodes[n].viewDepth = viewDepth();
  nodes[n].windowDepth = windowDepth();
  nodes[n].part = uint(partIndex);
  nodes[n].primitive = uint(gl_PrimitiveID);
  nodes[n].next = atomicExchange(heads[pixelIndex()], n);
})";

const char* kResolve = R"(
struct Key { float view, window; uint part, primitive; };
Key keyOf(uint n) { return Key(nodes[n].viewDepth, nodes[n].windowDepth, nodes[n].part, nodes[n].primitive); }
bool inFront(Key a, Key b) {
  if (a.view != b.view) return a.view < b.view;
  if (a.window != b.window) return a.window < b.window;
  if (a.part != b.part) return a.part < b.part;
  return a.primitive < b.primitive;
}
vec3 over(uint n, vec3 behind) {  // OVER: c·α + C·(1 − α)
  vec4 c = nodes[n].colour;
  return c.rgb * c.a + behind * (1.0 - c.a);
}
// Back to front without a local array, in one loop: each pass over the list finds the two
// farthest nodes in front of `previous` (keys are unique: a triangle covers a pixel once), and
// its end composites them and starts the next pass.
bool resolve(vec3 bg0, vec3 bg1, out vec3 r0, out vec3 r1) {
  uint head = heads[pixelIndex()];
  if (head == NONE) return false;
  r0 = bg0;
  r1 = bg1;
  const float inf = uintBitsToFloat(0x7f800000u);
  Key previous = Key(inf, inf, NONE, NONE);  // behind every fragment
  Key far1 = previous, far2 = previous;      // far1 behind far2
  uint node1 = NONE, node2 = NONE;
  uint node = head;
  for (;;) {
    if (node == NONE) {
      if (node1 == NONE) break;
      r0 = over(node1, r0);
      r1 = over(node1, r1);
      if (node2 == NONE) break;  // the list had one node left
      r0 = over(node2, r0);
      r1 = over(node2, r1);
      previous = far2;
      node1 = node2 = NONE;
      node = head;
      continue;
    }
    Key k = keyOf(node);
    if (inFront(k, previous)) {
      if (node1 == NONE || inFront(far1, k)) {
        far2 = far1;
        node2 = node1;
        far1 = k;
        node1 = node;
      } else if (node2 == NONE || inFront(far2, k)) {
        far2 = k;
        node2 = node;
      }
    }
    node = nodes[node].next;
  }
  return true;
})";

}  // namespace

std::string abuffer(GlFrame& f, const MethodOptions& o) {
  if (!o.is("precision", "float"))
    throw std::invalid_argument("glcheck runs abuffer with precision=float only (got precision=" + o.text("precision") + ")");
  const FrameContext& frame = f.context();
  const FragmentCounts counts = countTransparentFragments(frame);
  if (resolveIterations(counts.deepest) > kLoopIterations)
    throw std::invalid_argument(
        "glcheck abuffer: pixel (" + std::to_string(counts.deepestX) + ", " + std::to_string(counts.deepestY) + ") has " +
        std::to_string(counts.deepest) + " transparent fragments; resolving them takes " +
        std::to_string(resolveIterations(counts.deepest)) + " loop iterations, and llvmpipe ends a shader's loops after " +
        std::to_string(kLoopIterations) + " (LP_MAX_TGSI_LOOP_ITERATIONS)");
  // Room for a few more than oitref counted, in case its profile's raster rule is not the
  // driver's; a list cut short by a full buffer shows as a difference, never as a crash.
  const uint64_t capacity = counts.total + counts.total / 64 + 1024;
  if (capacity >= 0xffffffffu) throw std::invalid_argument("glcheck abuffer: more fragments than 32-bit node indices");

  f.opaquePass();
  const size_t pixels = size_t(frame.width) * size_t(frame.height);
  const std::vector<uint32_t> empty(pixels, 0xffffffffu);
  const uint32_t counter[2] = {0, uint32_t(capacity)};
  f.storageBuffer(0, pixels * sizeof(uint32_t), empty.data());
  f.storageBuffer(1, size_t(capacity) * 48, nullptr);  // std430: a Node is 48 bytes
  f.storageBuffer(2, sizeof counter, counter);
  const std::string storage = "const uint WIDTH = " + std::to_string(frame.width) + "u;\n" + kStorage;
  f.transparentPass("#extension GL_ARB_ES3_1_compatibility : require\n" + storage + kStore, {}, "depth", transparentState(frame.profile, BlendState{}));
  f.storageBarrier();
  f.compositeOntoBackgrounds(storage + kResolve, {});
  return "opaque";
}

}  // namespace oitref::glcheck
