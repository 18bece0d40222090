// What several of oitref's own methods share beyond the method kit (oitref/oit/method_kit.h): the
// weighted resolves and accumulations of the thesis's Algorithms 3–6. Each method file then reads
// like its paper's pseudocode.
#pragma once

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "methods/power.h"
#include "oitref/oit/method.h"
#include "oitref/oit/method_kit.h"

namespace oitref::methods {

// The one-channel format with the same encoding as an RGBA one: "rgba16f" → "r16f",
// "rgba:e8m7" → "r:e8m7" (a count or revealage beside an accumulation target).
inline std::string singleChannelFormat(const std::string& rgbaFormat) { return "r" + rgbaFormat.substr(4); }

// The bounds of the divisor Σα·w in S_oit. McGuire–Bavoil listing 3 clamps it to [1e-4, 5e4]
// (the default of WBOIT and MBOIT); thesis eq. 2.7 prints the quotient without a clamp, which
// bounds of ±∞ give (none). Unclamped, a divisor of 0 (a pixel no fragment reached, or only
// fragments of α = 0) would make the quotient 0/0 and the pixel NaN; there the average is taken as
// 0, what the clamped divisor gives, so the pixel keeps its background (eq. 2.5's factor
// 1 − Π(1 − α) is 0 there). The weighted average's divisor Σα (wavg) has only the lower bound
// 1e-4 (atLeast).
struct ResolveClamp {
  float low = 1e-4f, high = 5e4f;
  static constexpr ResolveClamp atLeast(float low) { return {low, std::numeric_limits<float>::infinity()}; }
  static constexpr ResolveClamp none() { return {-std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()}; }
  // sum / the clamped divisor; 0 where the divisor is 0.
  glm::vec3 average(const glm::vec3& sum, float divisor) const {
    const float d = std::clamp(divisor, low, high);
    return d == 0.0f ? glm::vec3(0.0f) : sum / d;
  }
};
// WBOIT's and MBOIT's option clamp=mb|none.
inline ResolveClamp resolveClampOption(const MethodOptions& o) {
  return o.is("clamp", "none") ? ResolveClamp::none() : ResolveClamp{};
}
// S_oit of WBOIT and MBOIT (thesis eq. 2.7; with McGuire–Bavoil listing 3's clamp by default):
// the weighted average accum.rgb / clamp(accum.a, low, high) and, as alpha, the revealage.
inline glm::vec4 weightedResolve(const glm::vec4& accum, float reveal, ResolveClamp clamp = {}) {
  return {clamp.average(glm::vec3(accum), accum.a), reveal};
}
// weightedResolve(accum[i], reveal[i], clamp) for i < n, two fragments at a time in eight vector
// lanes (the same comparisons and divisions lane for lane; a test holds it to weightedResolve).
inline void weightedResolveRow(const glm::vec4* accum, const float* reveal, int n, glm::vec4* out, ResolveClamp clamp = {}) {
  typedef float f8 __attribute__((vector_size(32)));
  const f8 lo = f8{} + clamp.low, hi = f8{} + clamp.high, zero = f8{};
  int i = 0;
  for (; i + 2 <= n; i += 2) {
    f8 a;
    std::memcpy(&a, accum + i, sizeof a);
    const f8 alpha = __builtin_shufflevector(a, a, 3, 3, 3, 3, 7, 7, 7, 7);
    const f8 divisor = alpha < lo ? lo : hi < alpha ? hi : alpha;  // std::clamp's comparisons
    f8 s = divisor == zero ? zero : a / divisor;
    s[3] = reveal[i], s[7] = reveal[i + 1];
    std::memcpy(out + i, &s, sizeof s);
  }
  for (; i < n; ++i) out[i] = weightedResolve(accum[i], reveal[i], clamp);
}

// (c.rgb·α, α), each channel's product rounded once in fp32, and α as it is: the premultiplied
// colour most methods accumulate, for one fragment in four vector lanes. GCC vectorised glm's
// form of it across a batch's fragments with a shuffle per channel and a store per float.
// With a weight w: (c.rgb·α·w, α·w), glm's (c.rgb·α)·w.
typedef float Float4Lanes __attribute__((vector_size(16)));
inline Float4Lanes premultipliedLanes(const glm::vec4& c) {
  Float4Lanes v;
  std::memcpy(&v, &c, sizeof v);
  return __builtin_shufflevector(v * __builtin_shufflevector(v, v, 3, 3, 3, 3), v, 0, 1, 2, 7);
}
inline glm::vec4 vec4Of(const Float4Lanes& p) {
  glm::vec4 out;
  std::memcpy(&out, &p, sizeof out);
  return out;
}
inline glm::vec4 premultiplied(const glm::vec4& c) { return vec4Of(premultipliedLanes(c)); }
inline glm::vec4 premultiplied(const glm::vec4& c, float w) {
  return vec4Of(premultipliedLanes(c) * Float4Lanes{w, w, w, w});
}
// (a.rgb + b.rgb·s, 1): a colour over a background b that keeps the weight s (wsum's composite,
// thesis Algorithm 2 step 11), each channel's product and sum rounded once in fp32 as in glm's
// vec3(a) + vec3(b)·s, in four vector lanes. GCC vectorised glm's form across the batch's pixels
// with a shuffle or two per channel: a fifth of the composite's time.
inline glm::vec4 plusScaledOpaque(const glm::vec4& a, const glm::vec4& b, float s) {
  Float4Lanes va, vb;
  std::memcpy(&va, &a, sizeof va);
  std::memcpy(&vb, &b, sizeof vb);
  const Float4Lanes r = va + vb * Float4Lanes{s, s, s, s};
  return vec4Of(__builtin_shufflevector(r, Float4Lanes{1.0f, 1.0f, 1.0f, 1.0f}, 0, 1, 2, 4));
}

// The accumulation shader's outputs for fragments [0, n): premultiplied(c, w) = (c.rgb·α·w, α·w)
// into `accum` and (α, α, α, α) into `reveal`, two fragments at a time in eight lanes (each lane
// premultipliedLanes's operations, so the same bits): one 32-byte load and two 32-byte stores
// for two fragments, where one fragment at a time took a load and two stores each.
inline void writeWeighted(const glm::vec4* colors, const float* w, int n, glm::vec4* accum, glm::vec4* reveal) {
  typedef float f8 __attribute__((vector_size(32)));
  int i = 0;
  for (; i + 2 <= n; i += 2) {
    f8 c;
    std::memcpy(&c, colors + i, sizeof c);
    const f8 alpha = __builtin_shufflevector(c, c, 3, 3, 3, 3, 7, 7, 7, 7);
    const f8 weight = {w[i], w[i], w[i], w[i], w[i + 1], w[i + 1], w[i + 1], w[i + 1]};
    const f8 r = __builtin_shufflevector(c * alpha, c, 0, 1, 2, 11, 4, 5, 6, 15) * weight;
    std::memcpy(accum + i, &r, sizeof r);
    std::memcpy(reveal + i, &alpha, sizeof alpha);
  }
  if (i < n) {
    const glm::vec4 c = colors[i];
    accum[i] = premultiplied(c, w[i]);
    reveal[i] = glm::vec4(c.a);
  }
}

// The accumulation pass of McGuire–Bavoil eq. 6 (listing 3), which WBOIT, MBOIT and MT share:
// accum cleared to 0 and reveal to 1 (by the pass: Framebuffer::clearColor), then
// accum += (c·α·w, α·w) blended ONE, ONE and reveal *= (1 − α) blended ZERO,
// ONE_MINUS_SRC_COLOR, against the opaque depth; weights(const FragmentBatch& in,
// const glm::vec4* colors, float* w) sets each fragment's w of a batch at once; `readsViewDepth`:
// whether it reads in.viewDepth (FragmentProgram::readsViewDepth; in.depth it may read either way).
Framebuffer weightedAccumulationTargets(FrameTargets& targets, Image& accum, Image& reveal);
PipelineState weightedAccumulationState(const Profile& profile);
template <typename Weights>
void accumulateWeightedBatch(PassRunner& run, FrameTargets& targets, Image& accum, Image& reveal, const Weights& weights,
                             bool readsViewDepth = true) {
  Framebuffer fb = weightedAccumulationTargets(targets, accum, reveal);
  run.transparentBatchPass("accumulate", fb, weightedAccumulationState(run.context().profile),
                           [&weights](const FragmentBatch& in, const glm::vec4* colors, FragmentBatchOutput& out) {
                             float w[kShaderBatch];
                             weights(in, colors, w);
                             writeWeighted(colors, w, in.count, out.colorRow(0), out.colorRow(1));
                             out.markWritten(in.count, 0b11u);
                           },
                           false, false, {}, true, readsViewDepth);
}

// The composite of WBOIT, MBOIT and stochastic transparency: weightedResolve(accum, reveal, clamp)
// blended over the background (PassRunner::blendOverBackground).
void compositeWeighted(PassRunner& run, FrameTargets& targets, const Image& accum, const Image& reveal,
                       ResolveClamp clamp = {});

// Bavoil–Myers's weighted average of n layers accumulated as (Σ c·α, Σ α) (n > 0): the average
// colour Σcα / max(Σα, 1e-4) (the divisor's bounds: `clamp`; ResolveClamp::none() divides by Σα
// as thesis eq. 2.3 prints it) and, as alpha, the transmittance T = max(0, 1 − Σα/n)^n.
inline glm::vec4 weightedAverageResolve(const glm::vec4& accum, float count, ResolveClamp clamp = ResolveClamp::atLeast(1e-4f)) {
  const float meanAlpha = accum.a / count;
  return {clamp.average(glm::vec3(accum), accum.a), powInt(std::max(0.0f, 1.0f - meanAlpha), unsigned(count))};
}

}  // namespace oitref::methods
