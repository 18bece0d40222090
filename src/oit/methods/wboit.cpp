// Weighted blended OIT (McGuire & Bavoil 2013, listing 3), Rožek's thesis Algorithm 4, eq. 2.5–2.7:
//   accum  += (c·α·w, α·w)            blended ONE, ONE
//   reveal *= (1 − α)                 blended ZERO, ONE_MINUS_SRC_COLOR, cleared to 1
//   composite (accum.rgb / clamp(accum.a, 1e-4, 5e4), reveal) blended into the background with
//   C_f = C_s·(1 − α_s) + C_d·α_s
// The clamp is McGuire–Bavoil's (listing 3); thesis eq. 2.7 divides by Σα·w as it is, which
// clamp=none gives (with W5 and a layer near the near plane the two differ by far more than
// rounding: tests/oit/test_printed_formulas.cpp).
// Weights w(z, α):
//   thesis W1–W5 on the window depth z ∈ [0,1] (with `adaptive`, z / z_s, z_s the opaque depth
//   at the pixel): one: 1, z3: 1/z³, z5: 1/z⁵, az3: α/z³, az5: α/z⁵. In exact arithmetic
//   `adaptive` changes nothing: every weight of a pixel gains the factor z_sᵏ, which cancels in
//   Σc·α·w / Σα·w. It shows only where that quotient is not taken exactly — the clamp of its
//   divisor (clamp=mb) and the accumulation format's range and rounding — which near the camera,
//   where 1/z⁵ is large, is what the thesis's fig. 3.12 shows.
//   McGuire–Bavoil on the view depth |z| (eq. 7–9) or the window depth d (eq. 10):
//   mb7:  α·clamp(10 / (1e-5 + (|z|/5)² + (|z|/200)⁶), 1e-2, 3e3)
//   mb8:  α·clamp(10 / (1e-5 + (|z|/10)³ + (|z|/200)⁶), 1e-2, 3e3)
//   mb9:  α·clamp(0.03 / (1e-5 + (|z|/200)⁴), 1e-2, 3e3)
//   mb10: α·max(1e-2, 3e3·(1 − d)³)
// Powers are products (methods/power.h), so the weights are the same bits everywhere.
//
// layout=single is McGuire–Bavoil listing 4, for GPUs without per-target blend state: one blend
// function for every target, with a separate alpha factor —
//   accum   = (Σ c·α·w, Π(1 − α))   RGB ONE, ONE; alpha ZERO, ONE_MINUS_SRC_ALPHA; cleared to (0,0,0,1)
//   weights = Σ α·w                 (R only: ONE, ONE)
// so the revealage lives in accum's alpha, at accum's precision (the `reveal` option does not
// apply), and the composite is (accum.rgb / clamp(weights, 1e-4, 5e4), accum.a).
#include <algorithm>
#include <stdexcept>

#include "methods/method_common.h"
#include "methods/methods.h"
#include "methods/power.h"

namespace oitref::methods {
namespace {

// The option weight=…, in the order of its choices (MethodOptions::choice).
enum class Weight { One, Z3, Z5, AZ3, AZ5, MB7, MB8, MB9, MB10 };

template <Weight Kind>
float weightAs(float alpha, float windowZ, float viewZ) {
  if constexpr (Kind == Weight::One) return 1.0f;
  else if constexpr (Kind == Weight::Z3) return 1.0f / powInt<3>(windowZ);
  else if constexpr (Kind == Weight::Z5) return 1.0f / powInt<5>(windowZ);
  else if constexpr (Kind == Weight::AZ3) return alpha / powInt<3>(windowZ);
  else if constexpr (Kind == Weight::AZ5) return alpha / powInt<5>(windowZ);
  else if constexpr (Kind == Weight::MB7) return alpha * std::clamp(10.0f / (1e-5f + powInt<2>(viewZ / 5.0f) + powInt<6>(viewZ / 200.0f)), 1e-2f, 3e3f);
  else if constexpr (Kind == Weight::MB8) return alpha * std::clamp(10.0f / (1e-5f + powInt<3>(viewZ / 10.0f) + powInt<6>(viewZ / 200.0f)), 1e-2f, 3e3f);
  else if constexpr (Kind == Weight::MB9) return alpha * std::clamp(0.03f / (1e-5f + powInt<4>(viewZ / 200.0f)), 1e-2f, 3e3f);
  else return alpha * std::max(1e-2f, 3e3f * powInt<3>(1.0f - windowZ));  // MB10
}

// A stateless callable for weightAs<K>: its own type per weight, so that f below is compiled once
// per weight with the expression inlined (a function pointer would be one type for all).
template <Weight K>
constexpr auto kWeightOf = [](float alpha, float windowZ, float viewZ) { return weightAs<K>(alpha, windowZ, viewZ); };

// f(kWeightOf<K>) for the weight chosen at run time: decided once per call, so that a batch's loop
// runs the one expression (not a switch or an indirect call per fragment).
template <typename F>
auto withWeight(Weight kind, F&& f) {
  switch (kind) {
    case Weight::One: return f(kWeightOf<Weight::One>);
    case Weight::Z3: return f(kWeightOf<Weight::Z3>);
    case Weight::Z5: return f(kWeightOf<Weight::Z5>);
    case Weight::AZ3: return f(kWeightOf<Weight::AZ3>);
    case Weight::AZ5: return f(kWeightOf<Weight::AZ5>);
    case Weight::MB7: return f(kWeightOf<Weight::MB7>);
    case Weight::MB8: return f(kWeightOf<Weight::MB8>);
    case Weight::MB9: return f(kWeightOf<Weight::MB9>);
    case Weight::MB10: break;
  }
  return f(kWeightOf<Weight::MB10>);
}

// McGuire–Bavoil's eq. 7–9 read the view depth; the others only the window depth (or none).
bool readsViewDepth(Weight kind) { return kind == Weight::MB7 || kind == Weight::MB8 || kind == Weight::MB9; }

float weight(Weight kind, float alpha, float windowZ, float viewZ) {
  return withWeight(kind, [&](auto w) { return w(alpha, windowZ, viewZ); });
}

class Wboit final : public OpaqueFirstMethod {
 public:
  explicit Wboit(const MethodOptions& o)
      : weight_(o.choice<Weight>("weight")),
        adaptive_(o.flag("adaptive")), single_(o.is("layout", "single")),
        clamp_(resolveClampOption(o)) {
    // The thesis makes its own weights W1–W5 adaptive (z / z_s in place of z); McGuire–Bavoil's
    // eq. 7–10 have no adaptive form (7–9 read the view depth, where z / z_s would mean nothing).
    if (adaptive_ && weight_ >= Weight::MB7)
      throw std::invalid_argument("method 'wboit' option 'adaptive': defined for the thesis weights one, z3, z5, az3, az5 only, not " +
                                  o.text("weight"));
    if (single_) {
      accum_ = declared.color("accum", o.format("accum"), "(Σ c·α·w, Π(1 − α)): RGB ONE, ONE; alpha ZERO, ONE_MINUS_SRC_ALPHA");
      weights_ = declared.color("weights", singleChannelFormat(o.text("accum")), "Σ α·w, the same blend function");
      return;
    }
    accum_ = declared.color("accum", o.format("accum"), "C2q: Σ(c·α·w, α·w), blended ONE, ONE");
    reveal_ = declared.color("reveal", o.format("reveal"), "C2s: Π(1 − α), blended ZERO, ONE_MINUS_SRC_COLOR");
  }
  const MethodInfo& info() const override { return wboitInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {  // after steps 1–3, the opaque pass
    if (single_) {
      accumulateSingle(context, t, run);
      return;
    }
    Image& accum = t[accum_];
    Image& reveal = t[reveal_];
    const DepthBuffer& depth = t.depth();
    // Steps 5–6 (reveal cleared to 1, accum to 0: by the pass, tile by tile), then steps 4,
    // 7–12: accum += (c·α·w, α·w) (S_accum, eq. 2.6), reveal *= (1 − α).
    const Weight kind = weight_;
    const bool adaptive = adaptive_;
    accumulateWeightedBatch(run, t, accum, reveal, [&](const FragmentBatch& in, const glm::vec4* c, float* w) {
      const int count = in.count;
      // The inputs as local rows, so that the weight's loop runs in vector lanes.
      float z[kShaderBatch], alpha[kShaderBatch], view[kShaderBatch];
      for (int i = 0; i < count; ++i) z[i] = in.depth[i], alpha[i] = c[i].a, view[i] = in.viewDepth[i];
      if (adaptive)
        for (int i = 0; i < count; ++i) z[i] = z[i] / float(depth.depth(in.x[i], in.y));  // z / z_s: the opaque depth behind it
      // Straight into w (the caller's local array): through a local row and std::copy_n, each
      // batch paid a call of memcpy.
      withWeight(kind, [&](auto weightOf) {
        for (int i = 0; i < count; ++i) w[i] = weightOf(alpha[i], z[i], view[i]);
      });
    }, readsViewDepth(kind));
    // Steps 13–14: S_oit (eq. 2.7) blended into the background.
    compositeWeighted(run, t, accum, reveal, clamp_);
  }

 private:
  // Listing 4.
  void accumulateSingle(const FrameContext& context, FrameTargets& t, PassRunner& run) {
    Image& accum = t[accum_];
    Image& weights = t[weights_];
    const DepthBuffer& depth = t.depth();
    accum.clear({0, 0, 0, 1}, context.profile);
    weights.clear({0, 0, 0, 1}, context.profile);
    Framebuffer fb;
    fb.color[0] = &accum;
    fb.color[1] = &weights;
    fb.depth = &t.depth();
    PipelineState st = transparentState(context.profile, singleTargetWeightedBlend());
    const Weight kind = weight_;
    const bool adaptive = adaptive_;
    run.transparentPass("accumulate", fb, st, [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput& out) {
      float z = in.depth;
      if (adaptive) z = z / float(depth.depth(in.x, in.y));
      const float w = weight(kind, c.a, z, in.viewDepth);
      out.write(0, glm::vec4(glm::vec3(c) * c.a * w, c.a));
      out.write(1, glm::vec4(c.a * w));
    });
    run.blendOverBackground(t, [&](const FragmentInput& in, glm::vec4& s) {
      const glm::vec4 a = accum.fetch(in.x, in.y);
      s = weightedResolve(glm::vec4(glm::vec3(a), weights.fetch(in.x, in.y).r), a.a, clamp_);
      return true;
    });
  }

  ColorHandle accum_, reveal_, weights_;  // reveal_ with layout=mrt, weights_ with layout=single
  Weight weight_;
  bool adaptive_, single_;
  ResolveClamp clamp_;
};

}  // namespace

const MethodInfo& wboitInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "wboit",
      "weighted blended OIT (McGuire–Bavoil listing 3; thesis Algorithm 4)",
      {{"accum", "rgba32f", "accumulation format (the thesis's Algorithm 4 uses RGBA32F; bfloat16 = rgba:e8m7, fp8 = rgba:e5m2)",
        {"rgba16f", "rgba32f", "rgba:e8m7", "rgba:e5m2"}},
       {"reveal", "r32f", "revealage format (thesis: R32F; McGuire–Bavoil: R8)", {"r8", "r16f", "r32f"}},
       {"weight", "az5", "w(z, α): thesis W1–W5 (one, z3, z5, az3, az5) or McGuire–Bavoil eq. 7–10 (mb7 … mb10)",
        {"one", "z3", "z5", "az3", "az5", "mb7", "mb8", "mb9", "mb10"}},
       {"adaptive", "false", "thesis weights one…az5 on z / z_s, z_s the opaque depth at the pixel (not for mb7…mb10)", {"true", "false"}},
       {"layout", "mrt", "mrt: listing 3 (per-target blending); single: listing 4 (one blend function, revealage in accum.a)",
        {"mrt", "single"}},
       {"clamp", "mb", "the composite's divisor Σα·w: mb = McGuire–Bavoil listing 3's clamp to [1e-4, 5e4]; none = thesis eq. 2.7 as printed (Σα·w itself, and 0 where it is 0: the background stays)",
        {"mb", "none"}}},
      {{"thesis", "Algorithm 4 as printed: C2q RGBA32F, C2s R32F, W5 (the weight of most of the thesis's figures), eq. 2.7 without a clamp",
        {{"accum", "rgba32f"}, {"reveal", "r32f"}, {"weight", "az5"}, {"adaptive", "false"}, {"layout", "mrt"}, {"clamp", "none"}}}}};
    // The study rows: Algorithm 4 as printed, the thesis's "WBOIT 16F" (no weight, the 16-bit
    // targets of its weighted average), its other weights in RGBA32F, and McGuire–Bavoil's own
    // set-up (RGBA16F + R8) with their equations 7–10.
    i.studyVariants = {
        {{"preset", "thesis"}},
        {{"preset", "thesis"}, {"weight", "one"}, {"accum", "rgba16f"}, {"reveal", "r16f"}},
        {{"weight", "z3"}},
        {{"weight", "z5"}},
        {{"weight", "az3"}},
        {{"weight", "az5"}, {"adaptive", "true"}},
        {{"weight", "az5"}, {"accum", "rgba16f"}},
        {{"weight", "mb7"}, {"accum", "rgba16f"}, {"reveal", "r8"}},
        {{"weight", "mb8"}, {"accum", "rgba16f"}, {"reveal", "r8"}},
        {{"weight", "mb9"}, {"accum", "rgba16f"}, {"reveal", "r8"}},
        {{"weight", "mb10"}, {"accum", "rgba16f"}, {"reveal", "r8"}},
        // Listing 4: one blend function, the revealage in accum's alpha.
        {{"layout", "single"}, {"accum", "rgba16f"}}};
    i.stressVariants = {{},
                        {{"accum", "rgba16f"}},
                        {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}},
                        {{"accum", "rgba16f"}, {"weight", "one"}},
                        {{"accum", "rgba:e8m7"}},
                        {{"accum", "rgba:e5m2"}}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> wboitFactory(const MethodOptions& o) { return std::make_unique<Wboit>(o); }

}  // namespace oitref::methods
