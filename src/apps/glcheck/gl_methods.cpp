#include "glcheck/gl_methods.h"

#include <stdexcept>
#include <map>

#include "blend/method_blend_states.h"
#include "methods/det_math.h"
#include "methods/method_common.h"
#include "methods/methods.h"
#include "methods/sorted_order.h"

namespace oitref::glcheck {
namespace {


PipelineState plainState() { return PipelineState{}; }

// opaque.cpp: everything drawn opaque.
std::string opaque(GlFrame& f, const MethodOptions&) {
  f.opaquePass(/*everything=*/true);
  return "opaque";
}

// over.cpp: OVER in submission order onto the background, its draws culled as `faces` says.
std::string over(GlFrame& f, const MethodOptions& o) {
  f.opaquePass();
  for (const auto& [name, cull] : methods::overDraws(o.text("faces"))) {
    PipelineState state = transparentState(f.context().profile, overBlend());
    state.raster.cull = cull;
    f.transparentPass(R"(
void main() {
  vec4 c = shadeSurface();
  o0 = c;
  o1 = c;
})",
                      {"opaque", "analysis"}, "depth", state);
  }
  return "opaque";
}

// sorted.cpp: OVER in the order of methods::sortedTriangleOrder (farthest centroid first).
std::string sorted(GlFrame& f, const MethodOptions& o) {
  f.opaquePass();
  std::vector<std::pair<size_t, size_t>> order;
  for (const methods::SortedTriangle& t : methods::sortedTriangleOrder(f.context(), o.is("sort", "triangle")))
    order.emplace_back(t.part, t.index);
  f.transparentPassInOrder(order, R"(
void main() {
  vec4 c = shadeSurface();
  o0 = c;
  o1 = c;
})",
                           {"opaque", "analysis"}, "depth", transparentState(f.context().profile, overBlend()));
  return "opaque";
}

// wsum.cpp: Σ(c·α, α), then C_f = C2.rgb + C1.rgb·(1 − C2.a) into "final".
std::string wsum(GlFrame& f, const MethodOptions&) {
  f.opaquePass();
  f.clear("accum", glm::vec4(0.0f));
  f.transparentPass(R"(
void main() {
  vec4 c = shadeSurface();
  o0 = vec4(c.rgb * c.a, c.a);
})",
                    {"accum"}, "depth", transparentState(f.context().profile, additiveBlend()));
  f.addScratch("analysis_in", "analysis");  // the composite writes the analysis copy it reads
  f.copy("analysis", "analysis_in");
  f.fullscreenPass(R"(
void main() {
  vec4 sum = fetch(accum);
  float background = 1.0 - sum.a;
  vec3 c1 = fetch(opaque).rgb, c0 = fetch(analysisIn).rgb;
  o0 = vec4(sum.rgb + c1 * background, 1.0);
  o1 = vec4(sum.rgb + c0 * background, 1.0);
})",
                   {"final", "analysis"}, plainState(),
                   {{"accum", "accum"}, {"opaque", "opaque"}, {"analysisIn", "analysis_in"}});
  return "final";
}

// ResolveClamp::average (method_common.h) in GLSL: sum / clampedDivisor, or unclamped (an empty
// clampedDivisor) sum / divisor with 0 where the divisor is 0.
std::string averageOf(const std::string& sum, const std::string& divisor, const std::string& clampedDivisor) {
  if (!clampedDivisor.empty()) return sum + " / " + clampedDivisor;
  return "(" + divisor + " == 0.0 ? vec3(0.0) : " + sum + " / " + divisor + ")";
}

// wavg.cpp: Σ(c·α, α) and n; (Σcα / max(Σα, 1e-4), T) over the background (clamp=none: Σcα / Σα).
std::string wavg(GlFrame& f, const MethodOptions& o) {
  f.opaquePass();
  f.clear("accum", glm::vec4(0.0f));
  f.clear("count", glm::vec4(0.0f));
  f.transparentPass(R"(
void main() {
  vec4 c = shadeSurface();
  o0 = vec4(c.rgb * c.a, c.a);
  o1 = vec4(1.0);
})",
                    {"accum", "count"}, "depth", transparentState(f.context().profile, additiveBlend()));
  const bool thesis = o.is("transmittance", "thesis_eq2.2");
  const std::string average = averageOf("a.rgb", "a.a", !o.is("clamp", "none") ? "max(a.a, " + glslFloat(1e-4f) + ")" : "");
  f.blendOverBackground(std::string(R"(
void main() {
  float n = fetch(count).r;
  if (n == 0.0) discard;
  vec4 a = fetch(accum);
  float meanAlpha = a.a / n;
  uint layers = uint(n);
  float tr = )") + (thesis ? "powInt(meanAlpha, layers)" : "powInt(max(0.0, 1.0 - meanAlpha), layers)") + R"(;
  vec4 s = vec4()" + average + R"(, tr);
  o0 = s;
  o1 = s;
})",
                        {{"count", "count"}, {"accum", "accum"}});
  return "opaque";
}

// wboit.cpp's w(z, α), as GLSL on (alpha, windowZ, viewZ).
std::string wboitWeight(const std::string& kind) {
  const std::map<std::string, std::string> w = {
      {"one", "1.0"},
      {"z3", "1.0 / powInt(windowZ, 3u)"},
      {"z5", "1.0 / powInt(windowZ, 5u)"},
      {"az3", "alpha / powInt(windowZ, 3u)"},
      {"az5", "alpha / powInt(windowZ, 5u)"},
      {"mb7", "alpha * clamp(10.0 / (E5 + powInt(viewZ / 5.0, 2u) + powInt(viewZ / 200.0, 6u)), E2, 3000.0)"},
      {"mb8", "alpha * clamp(10.0 / (E5 + powInt(viewZ / 10.0, 3u) + powInt(viewZ / 200.0, 6u)), E2, 3000.0)"},
      {"mb9", "alpha * clamp(C003 / (E5 + powInt(viewZ / 200.0, 4u)), E2, 3000.0)"},
      {"mb10", "alpha * max(E2, 3000.0 * powInt(1.0 - windowZ, 3u))"}};
  return "const float E5 = " + glslFloat(1e-5f) + ", E2 = " + glslFloat(1e-2f) + ", C003 = " + glslFloat(0.03f) +
         ";\nfloat weight(float alpha, float windowZ, float viewZ) { return " + w.at(kind) + "; }\n";
}

// weightedResolve (method_common.h): accum.rgb / clamp(accum.a, 1e-4, 5e4), revealage; with
// `clamped` false (clamp=none) accum.rgb / accum.a, 0 where accum.a is 0.
std::string weightedResolveMain(bool clamped = true) {
  return R"(
void main() {
  vec4 a = fetch(accum);
  vec4 s = vec4()" +
         averageOf("a.rgb", "a.a", clamped ? "clamp(a.a, " + glslFloat(1e-4f) + ", 50000.0)" : "") + R"(, fetch(reveal).r);
  o0 = s;
  o1 = s;
})";
}

// wboit.cpp: accum += (c·α·w, α·w), reveal *= (1 − α), resolve over the background.
std::string wboit(GlFrame& f, const MethodOptions& o) {
  if (!o.is("layout", "mrt"))
    throw std::invalid_argument("glcheck runs wboit with layout=mrt (listing 3) only (got layout=" + o.text("layout") + ")");
  f.opaquePass();
  f.clear("reveal", glm::vec4(1.0f));
  f.clear("accum", glm::vec4(0.0f));
  PipelineState st = transparentState(f.context().profile, additiveBlend());
  st.blend[1] = revealageBlend();
  const bool adaptive = o.flag("adaptive");
  std::vector<GlInput> inputs;
  if (adaptive) {  // reads the opaque depth it tests against
    f.addScratch("depth_in", "depth");
    f.copy("depth", "depth_in");
    inputs.push_back({"opaqueDepth", "depth_in"});
  }
  f.transparentPass(wboitWeight(o.text("weight")) + R"(
void main() {
  vec4 c = shadeSurface();
  float z = windowDepth();
)" + (adaptive ? "  z = z / fetch(opaqueDepth).r;\n" : "") + R"(
  float w = weight(c.a, z, viewDepth());
  o0 = vec4(c.rgb * c.a * w, c.a * w);
  o1 = vec4(c.a);
})",
                    {"accum", "reveal"}, "depth", st, inputs);
  f.blendOverBackground(weightedResolveMain(!o.is("clamp", "none")), {{"accum", "accum"}, {"reveal", "reveal"}});
  return "opaque";
}

// moment_math.cpp's four-power-moment absorbance (powerMomentAbsorbance) in fp32, as GLSL:
// `float absorbance(vec4 b, float z)` of the moments b (before the bias) at depth z.
std::string momentAbsorbanceGlsl(float bias, float overestimation, const std::string& biasVector) {
  return "const float BIAS = " + glslFloat(bias) + ", OVERESTIMATION = " + glslFloat(overestimation) +
         ";\nconst vec4 BIAS_VECTOR = " + biasVector + ";\n" + R"(
float absorbance(vec4 b, float z) {
  vec4 m = (1.0 - BIAS) * b + BIAS * BIAS_VECTOR;
  float d11 = m[1] - m[0] * m[0];
  float l21d11 = m[2] - m[0] * m[1];
  if (!(d11 > 0.0)) return OVERESTIMATION;
  float l21 = l21d11 / d11;
  float d22 = (m[3] - m[1] * m[1]) - l21d11 * l21;
  if (!(d22 > 0.0)) return OVERESTIMATION;
  float c0 = 1.0, c1 = z - m[0], c2 = z * z - m[1] - l21 * c1;
  c1 = c1 / d11;
  c2 = c2 / d22;
  c1 = c1 - l21 * c2;
  c0 = c0 - (c1 * m[0] + c2 * m[1]);
  float p = c1 / c2, q = c0 / c2;
  float disc = p * p * 0.25 - q;
  float r = sqrt(disc);
  float z1 = -p * 0.5 - r, z2 = -p * 0.5 + r;
  if (isnan(z1) || isinf(z1) || isnan(z2) || isinf(z2)) return OVERESTIMATION;
  float f0 = OVERESTIMATION, f1 = z1 < z ? 1.0 : 0.0, f2 = z2 < z ? 1.0 : 0.0;
  float f01 = (f1 - f0) / (z1 - z);
  float f12 = (f2 - f1) / (z2 - z1);
  float f012 = (f12 - f01) / (z2 - z);
  float a2 = f012;
  float a1 = f01 - f012 * (z + z1);
  precise float a0 = f0 - f01 * z + f012 * z * z1;  // precise: NIR would move the constant f0 last
  float result = a0 + a1 * m[0] + a2 * m[1];
  return (isnan(result) || isinf(result)) ? OVERESTIMATION : result;
}
)";
}

// mboit.cpp's depth warp into [−1, 1] and its 4-power-moment absorbance, as GLSL. ln and exp are the
// driver's fp32 log/exp, which mboit.cpp computes as llvmpipe does under math=llvmpipe
// (oitref/core/shader_builtins.h) and with det_math.h's in double otherwise.
std::string mboitFunctions(const MethodOptions& o, const Camera& camera) {
  if (!o.is("moments", "power4") || !o.is("storage", "float"))
    throw std::invalid_argument("glcheck runs mboit with moments=power4 storage=float only (got moments=" +
                                o.text("moments") + " storage=" + o.text("storage") + ")");
  const bool logWarp = o.is("warp", "log"), unitDepth = o.is("warp", "unit");
  const float bias = o.is("bias", "auto") ? 5e-7f : float(o.number("bias"));  // power4's published β
  const float logRange = float(methods::detLog(double(camera.farPlane) / double(camera.nearPlane)));
  return "const float NEAR = " + glslFloat(camera.nearPlane) + ", LOG_RANGE = " + glslFloat(logRange) +
         ", ALPHA_MAX = " + glslFloat(1.0f - 0x1p-20f) + ";\n" +
         (logWarp     ? "float warp() { return 2.0 * log(viewDepth() / NEAR) / LOG_RANGE - 1.0; }\n"
          : unitDepth ? "float warp() { return windowDepth(); }\n"
                      : "float warp() { return 2.0 * windowDepth() - 1.0; }\n") +
         momentAbsorbanceGlsl(bias, float(o.number("overestimation")), unitDepth ? "vec4(0.5)" : "vec4(0.0, 0.375, 0.0, 0.375)");
}

// The passes MBOIT and MT share: the moments of every fragment into (`total`, "moments"),
// blended ONE, ONE; then the WBOIT-style accumulation, whose shader reads them as totalMap and
// momentMap; then the resolve over the background. `momentsMain`, `weightMain`: their GLSL.
std::string momentWeightedFrame(GlFrame& f, const std::string& total, const std::string& momentsMain,
                                const std::string& weightMain, bool clamped) {
  f.opaquePass();
  f.clear(total, glm::vec4(0.0f));
  f.clear("moments", glm::vec4(0.0f));
  f.clear("accum", glm::vec4(0.0f));
  f.clear("reveal", glm::vec4(1.0f));
  const PipelineState additive = transparentState(f.context().profile, additiveBlend());
  f.transparentPass(momentsMain, {total, "moments"}, "depth", additive);
  PipelineState st = additive;
  st.blend[1] = revealageBlend();
  f.transparentPass(weightMain, {"accum", "reveal"}, "depth", st, {{"totalMap", total}, {"momentMap", "moments"}});
  f.blendOverBackground(weightedResolveMain(clamped), {{"accum", "accum"}, {"reveal", "reveal"}});
  return "opaque";
}

// mboit.cpp: moments of −ln(1 − α), then WBOIT-style accumulation with w = T(z), resolve.
std::string mboit(GlFrame& f, const MethodOptions& o) {
  const std::string functions = mboitFunctions(o, f.context().scene.camera);
  return momentWeightedFrame(f, "b0", functions + R"(
void main() {
  vec4 c = shadeSurface();
  float a = -log(1.0 - min(c.a, ALPHA_MAX));
  if (a < )" + glslFloat(1e-7f) + R"() discard;
  float z = warp(), z2 = z * z;
  o0 = vec4(a);
  o1 = vec4(z, z2, z2 * z, z2 * z2) * a;
})",
                             functions + R"(
void main() {
  vec4 c = shadeSurface();
  float b0 = fetch(totalMap).r;
  precise float w = 1.0;  // precise: NIR would multiply b0 by exp's log2(e) before the absorbance
  if (b0 >= )" + glslFloat(0.00100050033f) + R"() {
    vec4 m = fetch(momentMap) / b0;
    w = )" + std::string(o.is("saturate", "none") ? "exp(-b0 * absorbance(m, warp()))" : "clamp(exp(-b0 * absorbance(m, warp())), 0.0, 1.0)") + R"(;
  }
  o0 = vec4(c.rgb * c.a * w, c.a * w);
  o1 = vec4(c.a);
})",
                             !o.is("clamp", "none"));
}

// mt.cpp: optical depth and moments of u = ln(v/near)/ln(far/near), then WBOIT-style accumulation
// with w = exp(−optical depth · clamp(bound, 0, 1)), resolve. ln and exp as in mboit above.
std::string mt(GlFrame& f, const MethodOptions& o) {
  const Camera& camera = f.context().scene.camera;
  const float logRange = float(methods::detLog(double(camera.farPlane) / double(camera.nearPlane)));
  const std::string functions = "const float NEAR = " + glslFloat(camera.nearPlane) + ", LOG_RANGE = " +
                                glslFloat(logRange) + ", ALPHA_MAX = " + glslFloat(1.0f - 0.5f / 256.0f) + ";\n" +
                                "float unitDepth() { return log(viewDepth() / NEAR) / LOG_RANGE; }\n" +
                                momentAbsorbanceGlsl(float(o.number("bias")), 0.0f, "vec4(0.0, 0.375, 0.0, 0.375)");
  return momentWeightedFrame(f, "optical_depth", functions + R"(
void main() {
  vec4 c = shadeSurface();
  float a = -log(1.0 - min(c.a, ALPHA_MAX));
  float u = unitDepth(), u2 = u * u;
  o0 = vec4(a);
  o1 = vec4(u, u2, u2 * u, u2 * u2) * a;
})",
                             functions + R"(
void main() {
  vec4 c = shadeSurface();
  float total = fetch(totalMap).r;
  vec4 m = fetch(momentMap);
  if (total != 0.0) m = m / total;
  precise float w = exp(-clamp(absorbance(m, unitDepth()), 0.0, 1.0) * total);
  o0 = vec4(c.rgb * c.a * w, c.a * w);
  o1 = vec4(c.a);
})",
                             true);
}

// peel.cpp: each pass keeps the nearest layer strictly behind the previous one (compared in
// the d24 representation: the fragment's z and the stored depth both as round-to-even
// integers of z·(2^24 − 1), computed in double), blends it under the accumulator, and the
// accumulator finally goes onto the background.
std::string peel(GlFrame& f, const MethodOptions& o) {
  const int passes = int(o.number("passes"));
  f.clear("accum", glm::vec4(0, 0, 0, 1));
  f.clearDepth("peeled_depth", 0.0f);
  f.opaquePass();
  PipelineState solid;
  solid.depth = {true, CompareFunc::Less, true, false};
  PipelineState under;
  under.blend[0] = underBlend();
  for (int pass = 0; pass < passes; ++pass) {
    f.copy("depth", "layer_depth");
    f.clear("layer", glm::vec4(0.0f));
    f.transparentPass(R"(
void main() {
  const double M = 16777215.0lf;
  if (roundEven(double(windowDepth()) * M) <= roundEven(double(fetch(peeled).r) * M)) discard;
  vec4 c = shadeSurface();
  o0 = vec4(c.rgb * c.a, c.a);
})",
                      {"layer"}, "layer_depth", solid, {{"peeled", "peeled_depth"}});
    f.fullscreenPass("void main() { o0 = fetch(layer); }", {"accum"}, under, {{"layer", "layer"}});
    f.copy("layer_depth", "peeled_depth");
  }
  PipelineState merge;
  merge.blend[0] = merge.blend[1] = premultipliedOntoBackgroundBlend();
  f.fullscreenPass(R"(
void main() {
  vec4 c = fetch(accum);
  o0 = c;
  o1 = c;
})",
                   {"opaque", "analysis"}, merge, {{"accum", "accum"}});
  return "opaque";
}

// screendoor.cpp: drawn as opaque (LESS with depth writes, no blending) where α exceeds the
// pixel's Bayer threshold (B + ½)/N², else discarded; methods::bayerIndex as GLSL.
std::string screendoor(GlFrame& f, const MethodOptions& o) {
  const int n = int(o.number("mask"));
  f.opaquePass();
  PipelineState solid;
  solid.depth = {true, CompareFunc::Less, true, false};
  f.transparentPass("const int N = " + std::to_string(n) + ";\nconst float CELLS = " + glslFloat(float(n * n)) + R"(;
uint bayerIndex(int x, int y) {
  const uint quad[4] = uint[4](0u, 2u, 3u, 1u);
  uint b = 0u;
  for (int size = N; size > 1; size /= 2) {
    int bx = (x % size) / (size / 2), by = (y % size) / (size / 2);
    b += quad[by * 2 + bx] * uint((N / size) * (N / size));
  }
  return b;
}
void main() {
  vec4 c = shadeSurface();
  float threshold = (float(bayerIndex(int(gl_FragCoord.x), int(gl_FragCoord.y))) + 0.5) / CELLS;
  if (!(c.a > threshold)) discard;
  o0 = vec4(c.rgb, 1.0);
  o1 = vec4(c.rgb, 1.0);
})",
                    {"opaque", "analysis"}, "depth", solid);
  return "opaque";
}

// dualpeel.cpp as the sample writes it (every output of every fragment, MAX blending, which
// dualpeel.cpp's outputs=changing matches bit for bit): the init pass, then peeling passes until
// one peels no back layer — the sample's occlusion query, here a read of the back target — or
// `passes`, each blending its back layer over the background; finally the front onto it.
std::string dualpeel(GlFrame& f, const MethodOptions& o) {
  const int passes = int(o.number("passes"));
  f.opaquePass();
  PipelineState maxState = transparentState(f.context().profile, detail::states::kMax);
  maxState.blend[2] = detail::states::kMax;
  const std::string depth[2] = {"depth_a", "depth_b"}, front[2] = {"front_a", "front_b"};
  f.clear(depth[0], glm::vec4(-1.0f));
  f.clear(front[0], glm::vec4(0.0f));
  f.transparentPass("void main() { float z = windowDepth(); o0 = vec4(-z, z, 0.0, 0.0); }", {depth[0]}, "depth", maxState);
  PipelineState over;
  over.blend[0] = over.blend[1] = overBlend();
  int current = 0;
  for (int pass = 0; pass < passes; ++pass) {
    f.clear(depth[1 - current], glm::vec4(-1.0f));
    f.clear(front[1 - current], glm::vec4(0.0f));
    f.clear("back", glm::vec4(0.0f));
    f.transparentPass(R"(
void main() {
  vec4 c = shadeSurface();
  float z = windowDepth();
  vec4 range = fetch(depthPrev), frontSoFar = fetch(frontPrev);
  float nearest = -range.x, farthest = range.y;
  bool inside = z > nearest && z < farthest;
  bool isNearest = z == nearest, isFarthest = z == farthest && !isNearest;
  float multiplier = 1.0 - frontSoFar.a;
  vec4 under = vec4(frontSoFar.rgb + c.rgb * c.a * multiplier, 1.0 - multiplier * (1.0 - c.a));
  o0 = inside ? vec4(-z, z, 0.0, 0.0) : vec4(-1.0);
  o1 = isNearest ? under : frontSoFar;
  o2 = isFarthest ? c : vec4(0.0);
})",
                      {depth[1 - current], front[1 - current], "back"}, "depth", maxState,
                      {{"depthPrev", depth[current]}, {"frontPrev", front[current]}});
    f.fullscreenPass("void main() { vec4 b = fetch(back); if (b.a == 0.0) discard; o0 = b; o1 = b; }", {"opaque", "analysis"},
                     over, {{"back", "back"}});
    current = 1 - current;
    const Image back = f.read("back");
    bool peeled = false;
    for (int y = 0; y < back.height() && !peeled; ++y)
      for (int x = 0; x < back.width() && !peeled; ++x) peeled = back.fetch(x, y).a != 0.0f;
    if (!peeled) break;
  }
  PipelineState merge;
  merge.blend[0] = merge.blend[1] = detail::states::kFrontOntoBackground;
  f.fullscreenPass("void main() { vec4 c = fetch(front); o0 = c; o1 = c; }", {"opaque", "analysis"}, merge,
                   {{"front", front[current]}});
  return "opaque";
}

// stochastic.cpp (variant enderton): S stochastic depth passes, each keeping the fragments whose
// mask (methods::stochasticMask: SplitMix64 of the fragment's key, a partial Fisher–Yates
// shuffle, in 64-bit integers) has its sample; then the accumulation with v the share of samples
// whose stored depth is not in front (codes compared as peel compares them), and the composite.
std::string stochastic(GlFrame& f, const MethodOptions& o) {
  if (!o.is("variant", "enderton"))
    throw std::invalid_argument("glcheck runs stochastic with variant=enderton only (got variant=" + o.text("variant") + ")");
  const int samples = int(o.number("samples"));
  const uint32_t seed = uint32_t(o.number("seed"));
  f.opaquePass();
  PipelineState solid;
  solid.depth = {true, CompareFunc::Less, true, false};
  const std::string header = "#extension GL_ARB_gpu_shader_int64 : require\nconst int SAMPLES = " + std::to_string(samples) +
                             ";\nconst uint SEED = " + std::to_string(seed) + "u;\n";
  const std::string mask = R"(uniform int objectIndex;
uint64_t splitMix64(inout uint64_t state) {
  state += 0x9e3779b97f4a7c15ul;
  uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ul;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebul;
  return z ^ (z >> 31);
}
uint stochasticMask(float alpha) {
  int bits = clamp(int(floor(double(alpha) * double(SAMPLES) + 0.5lf)), 0, SAMPLES);
  uint64_t state = (uint64_t(SEED) << 32) ^ (uint64_t(uint(gl_FragCoord.x)) << 16) ^ uint64_t(uint(gl_FragCoord.y)) ^
                   (uint64_t(uint(objectIndex)) << 40) ^ (uint64_t(uint(gl_PrimitiveID)) * 0x2545f4914f6cdd1dul);
  splitMix64(state);
  int order[32];
  for (int i = 0; i < SAMPLES; ++i) order[i] = i;
  uint m = 0u;
  for (int i = 0; i < bits; ++i) {
    int j = i + int(splitMix64(state) % uint64_t(SAMPLES - i));
    int t = order[i]; order[i] = order[j]; order[j] = t;
    m |= 1u << uint(order[i]);
  }
  return m;
}
)";
  for (int s = 0; s < samples; ++s) {
    const std::string depth = "sample_depth_" + std::to_string(s);
    f.copy("depth", depth);
    f.transparentPass(header + mask + "void main() {\n  vec4 c = shadeSurface();\n  if (((stochasticMask(c.a) >> " +
                          std::to_string(s) + "u) & 1u) == 0u) discard;\n}",
                      {}, depth, solid);
  }
  f.clear("accum", glm::vec4(0.0f));
  f.clear("reveal", glm::vec4(1.0f));
  PipelineState st = transparentState(f.context().profile, additiveBlend());
  st.blend[1] = revealageBlend();
  std::string visible = "  const double M = 16777215.0lf;\n  double z = roundEven(double(windowDepth()) * M);\n  int visible = 0;\n";
  std::vector<GlInput> inputs;
  for (int s = 0; s < samples; ++s) {
    inputs.push_back({"sample" + std::to_string(s), "sample_depth_" + std::to_string(s)});
    visible += "  visible += z <= roundEven(double(fetch(sample" + std::to_string(s) + ").r) * M) ? 1 : 0;\n";
  }
  f.transparentPass("void main() {\n  vec4 c = shadeSurface();\n" + visible +
                        "  float v = float(visible) / float(" + std::to_string(samples) + ");\n"
                        "  o0 = vec4(c.rgb * c.a, c.a) * v;\n  o1 = vec4(c.a);\n}",
                    {"accum", "reveal"}, "depth", st, inputs);
  f.blendOverBackground(weightedResolveMain(), {{"accum", "accum"}, {"reveal", "reveal"}});
  return "opaque";
}

// meshkin3.cpp: t1 += (c·α, α) and t2 += (1/α, 1/α, 1/α, α) blended ONE, ONE; t3 *= (c, α) blended
// ZERO, SRC_COLOR; out = t1.rgb − bg·t1.a + bg·t3.a + bg·t2.rgb·t3.a.
std::string meshkin3(GlFrame& f, const MethodOptions&) {
  f.opaquePass();
  f.clear("t1", glm::vec4(0.0f));
  f.clear("t2", glm::vec4(0.0f));
  f.clear("t3", glm::vec4(1.0f));
  f.transparentPass(R"(
void main() {
  vec4 c = shadeSurface();
  o0 = vec4(c.rgb * c.a, c.a);
  o1 = vec4(vec3(1.0 / c.a), c.a);
})",
                    {"t1", "t2"}, "depth", transparentState(f.context().profile, additiveBlend()));
  f.transparentPass("void main() { o0 = shadeSurface(); }", {"t3"}, "depth",
                    transparentState(f.context().profile, detail::states::kProduct));
  f.compositeOntoBackgrounds(R"(
bool resolve(vec3 bg0, vec3 bg1, out vec3 r0, out vec3 r1) {
  vec4 s1 = fetch(t1), s2 = fetch(t2), s3 = fetch(t3);
  r0 = s1.rgb - bg0 * s1.a + bg0 * s3.a + bg0 * s2.rgb * s3.a;
  r1 = s1.rgb - bg1 * s1.a + bg1 * s3.a + bg1 * s2.rgb * s3.a;
  return true;
})",
                             {{"t1", "t1"}, {"t2", "t2"}, {"t3", "t3"}});
  return "opaque";
}

const std::vector<std::pair<std::string, GlMethod>>& registry() {
  static const std::vector<std::pair<std::string, GlMethod>> r = {
      {"opaque", opaque}, {"over", over}, {"wsum", wsum},   {"wavg", wavg},
      {"wboit", wboit},   {"mboit", mboit}, {"peel", peel}, {"screendoor", screendoor},
      {"dualpeel", dualpeel}, {"stochastic", stochastic}, {"meshkin3", meshkin3}, {"mt", mt}, {"sorted", sorted}, {"abuffer", abuffer}};
  return r;
}

}  // namespace

GlMethod findGlMethod(const std::string& name) {
  for (const auto& [n, m] : registry())
    if (n == name) return m;
  return nullptr;
}

std::vector<std::string> glMethodNames() {
  std::vector<std::string> names;
  for (const auto& [n, m] : registry()) names.push_back(n);
  return names;
}

}  // namespace oitref::glcheck
