#include "blend/blend_llvmpipe_float.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include <utility>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "blend/blend_math.h"
#include "blend/float_texels.h"
#include "blend/llvmpipe_float_arith.h"
#include "blend/method_blend_states.h"

namespace oitref::detail {
namespace {

using namespace llvmpipe_float;

// One pixel: its four channels in four lanes.
LP_INLINE v4f runPixel(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  const Inputs<v4f> in{Vec<v4f>::of(source), Vec<v4f>::of(destination), Vec<v4f>::of(constant),
                       splat(source[3]), splat(destination[3]), splat(constant[3]), v4i{0, 0, 0, -1},
                       plan.shape.hasAlpha};
  return run(plan, in);
}
// Eight lanes: the channels of 8 / channels pixels side by side, with each lane's pixel's
// source, destination and constant alpha beside them.
struct Lanes8 {
  v8f source, destination, constant, sourceAlpha, destinationAlpha, constantAlpha;
};
// `special`: as Arith's deferred (the caller blends the lanes again with it null where it is set);
// `hardwareFlush`: as Arith's hardware.
LP_INLINE v8f runLanes(const LlvmpipeFloatPlan& plan, const Lanes8& l, IntLanesOf<v8f>* special,
                       bool hardwareFlush = false) {
  const Inputs<v8f> in{Vec<v8f>::of(l.source), Vec<v8f>::of(l.destination), Vec<v8f>::of(l.constant),
                       l.sourceAlpha, l.destinationAlpha, l.constantAlpha, v8i{0, 0, 0, -1, 0, 0, 0, -1},
                       plan.shape.hasAlpha};
  return run(plan, in, special, hardwareFlush);
}

v4f general(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  return runPixel(plan, constant, source, destination);
}
// Eight lanes need AVX2's 256-bit integer operations (the DAZ, NaN and tiny tests); without it
// the compiler splits them into scalar code slower than four lanes twice. Chosen at run time
// (llvmpipeFloatTexelsFor); the same IEEE operations per lane as the four-lane path.
#define LP_AVX2 [[gnu::target("avx2")]]

// Pixels [0, n) blended again with every rare lane's rule applied, from the destinations' lanes
// as they were loaded: blendTexels's rare chunk. One function per layout with the shape read at run time
// (the same operations as a shape compiled in, which only folds them), so that each compiled
// function does not carry a second copy of the blend with the rules' scalar loops (most of this
// file's compile time). The plan and the constant's lanes come by value: by reference their
// addresses escaped, and the caller read its compiled shape back from memory after each call
// instead of folding it (twice as slow).
// A group's blend with the shape read at run time, out of line, for the general kernels and the
// rare chunks (blendAgainWithRules): inlined into each, the run-time shape's every branch took 55 s
// of this file's 86 s compile; the same operations per lane, so the same bits.
[[gnu::noinline]] LP_AVX2 v8f runLanesOutOfLine(const LlvmpipeFloatPlan& plan, const Lanes8& l, IntLanesOf<v8f>* special,
                                                 bool hardwareFlush = false) {
  return runLanes(plan, l, special, hardwareFlush);
}

template <typename Pixels>
[[gnu::noinline]] LP_AVX2 void blendAgainWithRules(LlvmpipeFloatPlan plan, v8f constant, v8f constantAlpha,
                                                   Pixels pixels, const v8f* loaded, int n, Rounding fp16) {
  Lanes8 lanes;
  lanes.constant = constant;
  lanes.constantAlpha = constantAlpha;
  for (int i = 0, g = 0; i < n; i += Pixels::P, g += 2) {
    pixels.loadSources(i, lanes.source, lanes.sourceAlpha);
    lanes.destination = loaded[g], lanes.destinationAlpha = loaded[g + 1];
    pixels.store(i, runLanesOutOfLine(plan, lanes, nullptr), fp16);
  }
}

#if defined(__x86_64__)
// llvmpipe's own floating-point mode for the guard's life: DAZ (bit 6) and FTZ (bit 15) set in
// the MXCSR, as Mesa sets them for its rasterizer threads (util_fpstate_set_denorms_to_zero);
// the caller's mode back after.
class FlushInHardware {
 public:
  // `caller`: the MXCSR now (LlvmpipeFloatPlan::callerMxcsr), or 0 to read it.
  explicit FlushInHardware(unsigned caller) : saved_(caller ? caller : _mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }
  ~FlushInHardware() { _mm_setcsr(saved_); }
  FlushInHardware(const FlushInHardware&) = delete;
  FlushInHardware& operator=(const FlushInHardware&) = delete;

 private:
  unsigned saved_;
};
#endif
// Whether a plan's denormal flushes can be left to the MXCSR (x86, and the fused multiply-adds in
// hardware too: std::fma in software does not follow the MXCSR).
bool flushesInHardware(const LlvmpipeFloatPlan& plan) {
#if defined(__x86_64__)
  return plan.flushDenormals && (!plan.fma || hardwareFma());
#else
  (void)plan;
  return false;
#endif
}

// `run` with the shape a compile-time constant; only the denormal mode and fma stay variables.
template <LlvmpipeFloatShape Shape>
LP_INLINE LlvmpipeFloatPlan withShape(const LlvmpipeFloatPlan& plan) {
  LlvmpipeFloatPlan p;
  // Field by field: copied as one object from the template parameter, GCC read the fields back
  // from memory in the kernel instead of folding them.
  p.shape.rs = Shape.rs, p.shape.rd = Shape.rd, p.shape.as = Shape.as, p.shape.ad = Shape.ad;
  p.shape.eqRgb = Shape.eqRgb, p.shape.eqAlpha = Shape.eqAlpha;
  p.shape.channels = Shape.channels, p.shape.hasAlpha = Shape.hasAlpha, p.shape.independent = Shape.independent;
  p.flushDenormals = plan.flushDenormals;
  p.fma = plan.fma;
  return p;
}
// How a kernel knows the shape: compiled in (KnownShape: its folds made when it is compiled, runLanes
// inlined) or read from the plan at run time (ShapeFromPlan: runLanesOutOfLine).
template <LlvmpipeFloatShape Shape>
struct KnownShape {
  static constexpr bool kKnown = true;
  LP_INLINE static LlvmpipeFloatPlan of(const LlvmpipeFloatPlan& plan) { return withShape<Shape>(plan); }
};
struct ShapeFromPlan {
  static constexpr bool kKnown = false;
  LP_INLINE static LlvmpipeFloatPlan of(const LlvmpipeFloatPlan& plan) { return plan; }
};

// Pixels [begin, end) (whole groups), then the padded group `tail` where there is one, blended
// with the rare lanes deferred into `special`, their destinations' lanes kept in `loaded`. Out of
// line, so that where the MXCSR flushes (HardwareFlush) the call keeps the arithmetic between the
// guard's two writes of the MXCSR. One loop body for both (the group's pixels chosen per group):
// the blend inlined once.
template <int Channels, typename ShapeOf, bool HardwareFlush, typename Pixels>
[[gnu::noinline]] LP_AVX2 void blendChunk(const LlvmpipeFloatPlan& planGiven, const Lanes8& constants,
                                          const Pixels& pixels, int begin, int end, const Pixels* tail, v8f* loaded,
                                          IntLanesOf<v8f>* special, Rounding fp16) {
  constexpr int P = 8 / Channels;
  const LlvmpipeFloatPlan plan = ShapeOf::of(planGiven);
  Lanes8 lanes = constants;
  IntLanesOf<v8f> rare{};  // in a register: through the pointer, every operation read and wrote memory
  const int groups = (end - begin) / P + (tail ? 1 : 0);
  for (int k = 0, g = 0; k < groups; ++k, g += 2) {
    const bool padded = tail && k == groups - 1;
    const Pixels& px = padded ? *tail : pixels;
    const int i = padded ? 0 : begin + k * P;
    px.loadDestinations(i, lanes.destination, lanes.destinationAlpha);
    loaded[g] = lanes.destination, loaded[g + 1] = lanes.destinationAlpha;
    px.loadSources(i, lanes.source, lanes.sourceAlpha);
    if constexpr (ShapeOf::kKnown) px.store(i, runLanes(plan, lanes, &rare, HardwareFlush), fp16);
    else px.store(i, runLanesOutOfLine(plan, lanes, &rare, HardwareFlush), fp16);
  }
  *special = rare;
}

// LlvmpipeFloatTexelsFn's and LlvmpipeFloatRunFn's loop, inlined into each compiled function. Up
// to kChunk pixels are blended with the rare lanes' rules deferred (Arith: one test for the chunk
// instead of one per operation and group); in the rare chunk that has such a lane, every pixel of
// it is blended again from the destinations as they were loaded, with the rules applied. The
// same bits either way. Where the profile flushes denormals, the chunk runs in llvmpipe's own
// MXCSR mode (FlushInHardware) where it can: the flushes cost nothing then, and only NaN lanes are
// rare (their payloads follow x86Nan's rule, which does not depend on the compiler's operand order).
// The pixels after the last whole group go with the last chunk as a padded group (PaddedGroup).
template <int Channels, bool Half, typename ShapeOf, typename Pixels>
LP_INLINE int blendTexels(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const Pixels& pixels, int n,
                          Rounding fp16) {
  constexpr int P = 8 / Channels, kChunk = 64;
  if (n <= 0) return 0;
  Lanes8 lanes;
  const v4f c = load4(constant);
  v4f cs[P];
  for (v4f& x : cs) x = c;
  gatherLanes<Channels>(cs, lanes.constant, lanes.constantAlpha);
  const int whole = n - n % P;
  const bool hardware = flushesInHardware(plan);
  // A kernel compiled for its shape has one chunk function, built for the MXCSR's flushes: it
  // runs in that mode, or for a plan that does not flush (then `hardware` changes nothing in
  // Arith). The software rule (a CPU without the fused multiply-add in hardware, or not x86)
  // takes the general chunk function: a second compiled copy of every shape doubled this file's
  // build time.
  if constexpr (ShapeOf::kKnown)
    if (plan.flushDenormals && !hardware) return blendTexels<Channels, Half, ShapeFromPlan>(plan, constant, pixels, n, fp16);
  const PaddedGroup<Channels, Half, Pixels> padded(pixels, whole, n - whole);  // filled only where n - whole > 0
  const Pixels tailLanes = padded.lanes();
  for (int chunk = 0; chunk < n; chunk += kChunk) {
    const int end = chunk + kChunk < whole ? chunk + kChunk : whole;
    const Pixels* tail = end == whole && whole < n ? &tailLanes : nullptr;
    v8f loaded[2 * kChunk / P + 2];  // each group's destination lanes and their alphas
    IntLanesOf<v8f> special{};
    bool done = false;
#if defined(__x86_64__)
    if (hardware) {
      const FlushInHardware mode(plan.callerMxcsr);
      blendChunk<Channels, ShapeOf, true>(plan, lanes, pixels, chunk, end, tail, loaded, &special, fp16);
      done = true;
    }
#endif
    if (!done) blendChunk<Channels, ShapeOf, ShapeOf::kKnown>(plan, lanes, pixels, chunk, end, tail, loaded, &special, fp16);
    if (Arith<v8f>::any(special)) {
      blendAgainWithRules(ShapeOf::of(plan), lanes.constant, lanes.constantAlpha, pixels.from(chunk), loaded,
                          end - chunk, fp16);
      if (tail) blendAgainWithRules(ShapeOf::of(plan), lanes.constant, lanes.constantAlpha, *tail,
                                    loaded + 2 * (end - chunk) / P, P, fp16);
    }
    if (end == whole) break;
  }
  if (whole < n) padded.writeBack(pixels, whole, n - whole);
  (void)hardware;
  return n;
}
template <int Channels, bool Half>
LP_AVX2 int generalTexels(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* const* sources,
                          uint8_t* const* texels, int n, Rounding fp16) {
  return blendTexels<Channels, Half, ShapeFromPlan>(plan, constant, ScatteredTexelLanes<Channels, Half>{sources, texels}, n, fp16);
}
template <int Channels, bool Half>
LP_AVX2 int generalRun(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* sources,
                       uint8_t* texels, int n, Rounding fp16) {
  return blendTexels<Channels, Half, ShapeFromPlan>(plan, constant, RunTexelLanes<Channels, Half>{sources, texels}, n, fp16);
}

template <LlvmpipeFloatShape Shape>
v4f compiled(const LlvmpipeFloatPlan& plan, v4f constant, v4f source, v4f destination) {
  return runPixel(withShape<Shape>(plan), constant, source, destination);
}
template <LlvmpipeFloatShape Shape, bool Half>
LP_AVX2 int compiledTexels(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* const* sources,
                           uint8_t* const* texels, int n, Rounding fp16) {
  return blendTexels<Shape.channels, Half, KnownShape<Shape>>(plan, constant,
                                           ScatteredTexelLanes<Shape.channels, Half>{sources, texels}, n, fp16);
}
template <LlvmpipeFloatShape Shape, bool Half>
LP_AVX2 int compiledRun(const LlvmpipeFloatPlan& plan, const glm::vec4& constant, const glm::vec4* sources,
                        uint8_t* texels, int n, Rounding fp16) {
  return blendTexels<Shape.channels, Half, KnownShape<Shape>>(plan, constant, RunTexelLanes<Shape.channels, Half>{sources, texels},
                                           n, fp16);
}

// One compiled function per method blend state and the float layouts it is drawn into (r, rg: no
// alpha; rgba), as kMethodFloatLayouts lists them.
struct CompiledEntry {
  LlvmpipeFloatShape shape;
  LlvmpipeFloatBlendFn fn;
  LlvmpipeFloatTexelFns texels[2];  // fp32, fp16
};
struct StateLayout {
  size_t state = 0;
  int channels = 0;
};
constexpr size_t kStateLayoutCount = [] {
  size_t n = 0;
  for (unsigned layouts : states::kMethodFloatLayouts) n += size_t(std::popcount(layouts));
  return n;
}();
constexpr auto kStateLayouts = [] {
  std::array<StateLayout, kStateLayoutCount> pairs{};
  size_t n = 0;
  for (size_t i = 0; i < std::size(states::kMethodFloatLayouts); ++i)
    for (int channels : {1, 2, 4})
      if (states::kMethodFloatLayouts[i] & unsigned(channels)) pairs[n++] = {i, channels};
  return pairs;
}();
template <StateLayout P>
constexpr CompiledEntry entry() {
  constexpr LlvmpipeFloatShape shape = llvmpipeFloatShape(P.channels, P.channels == 4, states::kMethodBlendStates[P.state]);
  return {shape,
          &compiled<shape>,
          {{&compiledTexels<shape, false>, &compiledRun<shape, false>}, {&compiledTexels<shape, true>, &compiledRun<shape, true>}}};
}
template <size_t... J>
constexpr auto compiledTable(std::index_sequence<J...>) {
  return std::array<CompiledEntry, sizeof...(J)>{entry<kStateLayouts[J]>()...};
}
constexpr auto kCompiled = compiledTable(std::make_index_sequence<kStateLayoutCount>());

}  // namespace

uint32_t floatModeOfThisThread() {
#if defined(__x86_64__)
  return _mm_getcsr();
#else
  return 0;
#endif
}

LlvmpipeFloatBlendFn llvmpipeFloatBlendFor(const LlvmpipeFloatShape& shape, bool specialised) {
  if (specialised)
    for (const CompiledEntry& e : kCompiled)
      if (e.shape == shape) return e.fn;
  return general;
}

LlvmpipeFloatTexelFns llvmpipeFloatTexelsFor(const LlvmpipeFloatShape& shape, bool half, bool specialised) {
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (!avx2) return {};
#endif
  if (specialised)
    for (const CompiledEntry& e : kCompiled)
      if (e.shape == shape) return e.texels[half];
  constexpr LlvmpipeFloatTexelFns general[3][2] = {
      {{generalTexels<1, false>, generalRun<1, false>}, {generalTexels<1, true>, generalRun<1, true>}},
      {{generalTexels<2, false>, generalRun<2, false>}, {generalTexels<2, true>, generalRun<2, true>}},
      {{generalTexels<4, false>, generalRun<4, false>}, {generalTexels<4, true>, generalRun<4, true>}}};
  return general[shape.channels == 4 ? 2 : shape.channels - 1][half];
}

glm::vec4 blendLlvmpipeFloat(const Format& format, const BlendState& state, const glm::vec4& constant, bool fma,
                             bool flushDenormals, const glm::vec4& source, const glm::vec4& destination) {
  LlvmpipeFloatPlan plan;
  plan.shape = llvmpipeFloatShape(format.channels, format.hasAlpha(), state);
  plan.flushDenormals = flushDenormals;
  plan.fma = fma;
  return store4(runPixel(plan, load4(constant), load4(source), load4(destination)));
}

}  // namespace oitref::detail
