// Moment-based OIT (Münstermann, Krumpen, Klein, Peters 2018), in the shape of Rožek's thesis
// Algorithm 6 (eq. 2.8–2.11), with the paper's moment sets and 16-bit storage:
//   pass 1:     b0 += A and b += A·moments(z),  A = −ln(1 − α); moments(z) = (z, z², …, z^N) for
//               N = 4, 6, 8 power moments, or (e^{iφ}, …, e^{ikφ}) for k = 2, 3, 4
//               trigonometric moments (moment_math.h). storage=float: fp32 targets blended
//               ONE, ONE. storage=unorm16: the normalised moments quantised into RGBA16/RG16
//               UNORM, updated per fragment in raster order (read, un-normalise, add,
//               re-normalise, write), as the paper does with rasterizer-ordered views.
//   pass 2:     w = T(z) = exp(−b0 · absorbance(b/b0, z)), accumulated as WBOIT does:
//               accum += (c·α·w, α·w), reveal *= (1 − α)
//   composite:  (accum.rgb / clamp(accum.a, 1e-4, 5e4), reveal) over the background
// absorbance: the moments biased towards the published vector with the published β (option
// bias=auto), then the Hankel (power) or Toeplitz (trigonometric) system and its polynomial's
// roots give the reconstructed depth distribution, weighted 1 in front of z, `overestimation`
// at z, 0 behind (moment_math.cpp).
// Depth z in [−1, 1]: warp=linear uses 2·d − 1 (d the window depth); warp=log uses
// 2·ln(v/near)/ln(far/near) − 1 (v the view depth), so the bias vectors fit both. warp=unit is
// the thesis's z = d in [0, 1], with Algorithm 5's bias vector (0.5, 0.5, 0.5, 0.5).
// Guards: α is clamped to 1 − 2^-20 (α = 1 would make A infinite); fragments with A below
// 1e-7 add no moments; in pass 2 a pixel with b0 < 0.00100050033 (its layers are all nearly
// clear) uses w = 1; moments that cannot be used fall back to absorbance = overestimation (the
// fragment's own layer), counted in the fact "moment reconstructions that fell back".
// Power moments clamp T to [0, 1] (saturate), trigonometric ones do not, as in the paper's code;
// saturate=none never clamps (thesis eq. 2.11). preset=thesis: Algorithms 5–6 as printed.
// ln, exp, sin and cos are det_math.h's, so the weights are the same bits on every machine.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "methods/det_math.h"
#include "oitref/core/shader_builtins.h"
#include "methods/method_common.h"
#include "methods/methods.h"
#include "methods/moment_math.h"
#include "methods/spread_count.h"

namespace oitref::methods {
namespace {

constexpr float kWrappingZoneAngle = 0.31415926535897932f;  // 0.1π, the paper code's default

// out[4j + k] = texels[used[j]][k] / b0[j] for j < n, k < 4: each an IEEE division (the bits do
// not depend on how many travel together), two fragments in eight lanes built in registers (put
// together in memory lane by lane, the divisions waited for the stores: no store forwarding).
void normaliseFourMoments(const glm::vec4* texels, const int* used, const float* b0, int n, float* out) {
  typedef float v4f __attribute__((vector_size(16)));
  typedef float v8f __attribute__((vector_size(32)));
  auto load = [&](int j) {
    v4f v;
    std::memcpy(&v, &texels[used[j]], sizeof v);
    return v;
  };
  int j = 0;
  for (; j + 2 <= n; j += 2) {
    const v8f m = __builtin_shufflevector(load(j), load(j + 1), 0, 1, 2, 3, 4, 5, 6, 7);
    const v8f d = {b0[j], b0[j], b0[j], b0[j], b0[j + 1], b0[j + 1], b0[j + 1], b0[j + 1]};
    const v8f q = m / d;
    std::memcpy(out + 4 * j, &q, sizeof q);
  }
  if (j < n) {
    const v4f q = load(j) / (v4f{} + b0[j]);
    std::memcpy(out + 4 * j, &q, sizeof q);
  }
}

class Mboit final : public OpaqueFirstMethod {
 public:
  explicit Mboit(const MethodOptions& o)
      : set_(MomentSet::parse(o.text("moments"))), quantised_(o.is("storage", "unorm16")),
        bias_(o.is("bias", "auto") ? set_.defaultBias(quantised_) : float(o.number("bias"))),
        overestimation_(float(o.number("overestimation"))), logWarp_(o.is("warp", "log")),
        unitDepth_(o.is("warp", "unit")), saturate_(o.is("saturate", "auto") && !set_.trigonometric),
        clamp_(resolveClampOption(o)) {
    // The thesis's depth in [0, 1] comes with its bias vector for four power moments (Algorithm 5);
    // the published vectors of the other sets and the 16-bit mapping assume depths in [−1, 1].
    if (unitDepth_ && (!o.is("moments", "power4") || quantised_))
      throw std::invalid_argument("method 'mboit' option 'warp': unit (the thesis's depth in [0, 1]) needs moments=power4 storage=float");
    const std::string blend = quantised_ ? "normalised and quantised, read-modify-write in raster order"
                                         : "blended ONE, ONE";
    const std::string four = quantised_ ? "rgba16" : "rgba32f", two = quantised_ ? "rg16" : "rg32f";
    b0_ = declared.color("b0", "r32f", "C_Ms: Σ −ln(1 − α), " + std::string(quantised_ ? "read-modify-write" : "blended ONE, ONE"));
    moments_ = declared.color("moments", four, momentRange(0, 4) + ", " + blend);
    if (set_.reals() > 4) momentsMore_ = declared.color("moments_more", set_.reals() == 6 ? two : four, momentRange(4, set_.reals()) + ", " + blend);
    accum_ = declared.color("accum", o.format("accum"), "Σ(c·α·w, α·w), blended ONE, ONE");
    reveal_ = declared.color("reveal", "r32f", "Π(1 − α), blended ZERO, ONE_MINUS_SRC_COLOR");
    // The composite is WBOIT's (compositeWeighted): accum and reveal only.
    declared.readBeforeCompositeOnly(b0_);
    declared.readBeforeCompositeOnly(moments_);
    if (set_.reals() > 4) declared.readBeforeCompositeOnly(momentsMore_);
  }
  const MethodInfo& info() const override { return mboitInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& result) override {
    const Profile& profile = context.profile;
    Image& b0Image = t[b0_];
    Image* momentImages[2] = {&t[moments_], set_.reals() > 4 ? &t[momentsMore_] : nullptr};
    Image& accum = t[accum_];
    Image& reveal = t[reveal_];
    if (quantised_) {  // read and written by the shader; otherwise the moment pass's attachments, which it clears
      b0Image.clear(glm::vec4(0.0f), profile);
      for (Image* m : momentImages)
        if (m) m->clear(glm::vec4(0.0f), profile);
    }
    // accum and reveal: cleared by their pass (accumulateWeightedBatch).
    const Camera& cam = context.scene.camera;
    const double logRange = detLog(double(cam.farPlane) / double(cam.nearPlane));
    const bool logWarp = logWarp_;
    // The warped depth of fragment i of a batch: linear 2·d − 1, unit d (× 1 and − 0 change no
    // bits), or the log of the view depth.
    const float warpScale = unitDepth_ ? 1.0f : 2.0f, warpOffset = unitDepth_ ? 0.0f : 1.0f;
    auto linearWarp = [warpScale, warpOffset](const FragmentBatch& in, int i) { return warpScale * in.depth[i] - warpOffset; };
    const bool readsViewDepth = logWarp;  // linearWarp reads only the window depth
    // math=llvmpipe: the GLSL's fp32 expressions (src/apps/glcheck/gl_methods.cpp, mboit) with the
    // driver's log and exp (oitref/core/shader_builtins.h); LOG_RANGE is the double's float.
    const bool driverMath = profile.math == ShaderMath::Llvmpipe, fused = profile.fma;
    const float logRangeFloat = float(logRange);
    auto warp = [&, logWarp](const FragmentBatch& in, int i) {
      if (!logWarp) return linearWarp(in, i);
      if (driverMath) return 2.0f * llvmpipe::log(in.viewDepth[i] / cam.nearPlane, fused) / logRangeFloat - 1.0f;
      return float(2.0 * detLog(double(in.viewDepth[i]) / double(cam.nearPlane)) / logRange - 1.0);
    };
    // A = float(−detLog(1 − α)), α clamped below 1; the logarithms of a batch together
    // (detLogFloatBatch: float(detLog) for each; float(−v) is −float(v)).
    auto logArgument = [](float alpha) { return 1.0 - double(std::min(alpha, 1.0f - 0x1p-20f)); };
    // A batch whose alphas are one bit pattern (a material's constant alpha: most of them) takes
    // one logarithm (detLogFloat, as detLogFloatBatch takes it for a batch of one value), and
    // none when it is the alpha of the thread's last such batch (usually the same object's).
    auto absorbancesOf = [&](const glm::vec4* colors, int count, float* a) {
      if (driverMath) {  // −log(1.0 − min(c.a, ALPHA_MAX))
        float x[kShaderBatch];
        x[0] = 1.0f - std::min(colors[0].a, 1.0f - 0x1p-20f);  // a batch is never empty (said so, GCC sees x written)
        for (int i = 1; i < count; ++i) x[i] = 1.0f - std::min(colors[i].a, 1.0f - 0x1p-20f);
        llvmpipe::logBatch(x, a, count, fused);
        for (int i = 0; i < count; ++i) a[i] = -a[i];
        return;
      }
      const uint32_t first = std::bit_cast<uint32_t>(colors[0].a);  // a batch is never empty
      bool oneAlpha = true;
      for (int i = 1; i < count; ++i) oneAlpha &= std::bit_cast<uint32_t>(colors[i].a) == first;
      if (oneAlpha) {
        thread_local struct {
          uint64_t alpha = ~uint64_t(0);  // no float's bits
          float absorbance = 0.0f;
        } last;
        if (last.alpha != first) last = {first, -detLogFloat(logArgument(colors[0].a))};
        std::fill_n(a, count, last.absorbance);
        return;
      }
      double x[kShaderBatch];
      float ln[kShaderBatch];
      x[0] = logArgument(colors[0].a);  // said so, GCC sees x written
      for (int i = 1; i < count; ++i) x[i] = logArgument(colors[i].a);
      detLogFloatBatch(x, ln, count);
      for (int i = 0; i < count; ++i) a[i] = -ln[i];
    };
    const MomentSet set = set_;
    const int reals = set.reals();
    const WrappingZone zone = WrappingZone::fromAngle(set.trigonometric ? kWrappingZoneAngle : 0.0f);
    // A pixel's stored moments from its texels: lo the first four, hi the rest.
    auto gatherMoments = [reals](const glm::vec4& lo, const glm::vec4& hi, float* out) {
      for (int k = 0; k < reals; ++k) out[k] = k < 4 ? lo[k] : hi[k - 4];
    };

    Framebuffer momentFb;
    momentFb.depth = &t.depth();
    // The usual set — four power moments in fp32, the depth warped linearly or not at all —
    // runs passes of its own, decided here once: no per-fragment branch on the configuration.
    const bool usualSet = !quantised_ && reals == 4 && !set.trigonometric && !logWarp_;
    if (!quantised_) {
      momentFb.color[0] = &b0Image;
      momentFb.color[1] = momentImages[0];
      momentFb.color[2] = momentImages[1];
      for (int k = 0; k < 3; ++k)  // cleared to 0 by the pass, tile by tile (Framebuffer::clearColor)
        if (momentFb.color[size_t(k)]) momentFb.clearColor[size_t(k)] = glm::vec4(0.0f);
      // Blended ONE, ONE: writeMoments(in, i, A, out) writes fragment i's b0 and moments, or
      // nothing when it is nearly clear (A below 1e-7 adds nothing measurable).
      auto momentPass = [&](auto writeMoments) {
        run.transparentBatchPass("moments", momentFb, transparentState(profile, additiveBlend()),
                                 [&](const FragmentBatch& in, const glm::vec4* colors, FragmentBatchOutput& out) {
                                   float absorbance[kShaderBatch];
                                   absorbancesOf(colors, in.count, absorbance);
                                   for (int i = 0; i < in.count; ++i) writeMoments(in, i, absorbance[i], out);
                                 },
                                 false, false, {}, true, readsViewDepth);
      };
      if (usualSet)
        momentPass([&](const FragmentBatch& in, int i, float a, FragmentBatchOutput& out) {
          const bool adds = !(a < 1e-7f);
          out.writeIf(i, 0, glm::vec4(a), adds);
          out.writeIf(i, 1, PowerMoments(linearWarp(in, i)).firstFour() * a, adds);
        });
      else
        momentPass([&](const FragmentBatch& in, int i, float a, FragmentBatchOutput& out) {
          if (a < 1e-7f) return;
          float m[8] = {};
          momentsOf(set, warp(in, i), zone, m);
          out.write(i, 0, glm::vec4(a));
          out.write(i, 1, glm::vec4(m[0], m[1], m[2], m[3]) * a);
          if (reals > 4) out.write(i, 2, glm::vec4(m[4], m[5], m[6], m[7]) * a);
        });
    } else {
      // Read-modify-write in raster order: a batch's fragments lie in distinct pixels of one row,
      // and the batches of a pixel come in primitive order, so a batch reads its texels, updates
      // them and writes them back as each fragment would alone.
      run.transparentBatchPass("moments", momentFb, transparentState(profile, BlendState{}),
                               [&](const FragmentBatch& in, const glm::vec4* colors, FragmentBatchOutput&) {
                                 const int count = in.count;
                                 float absorbance[kShaderBatch];
                                 absorbancesOf(colors, count, absorbance);
                                 glm::vec4 b0s[kShaderBatch], lo[kShaderBatch], hi[kShaderBatch];
                                 fetchTexels(b0Image, in, b0s);
                                 fetchTexels(*momentImages[0], in, lo);
                                 if (momentImages[1]) fetchTexels(*momentImages[1], in, hi);
                                 int xs[kShaderBatch], n = 0;  // the fragments that add moments, and their texels
                                 for (int i = 0; i < count; ++i) {
                                   const float a = absorbance[i];
                                   if (a < 1e-7f) continue;
                                   float q[8] = {}, m[8] = {}, mq[8] = {};
                                   float b0 = b0s[i].r;
                                   gatherMoments(lo[i], hi[i], q);
                                   offsetQuantised(set, q, -1.0f);
                                   for (int k = 0; k < reals; ++k) q[k] *= b0;
                                   momentsOf(set, warp(in, i), zone, m);
                                   quantiseMoments(set, m, mq);
                                   b0 += a;
                                   for (int k = 0; k < reals; ++k) q[k] = (q[k] + mq[k] * a) / b0;
                                   offsetQuantised(set, q, 1.0f);
                                   xs[n] = in.x[i];
                                   b0s[n] = glm::vec4(b0);
                                   lo[n] = glm::vec4(q[0], q[1], q[2], q[3]);
                                   hi[n++] = glm::vec4(q[4], q[5], q[6], q[7]);
                                 }
                                 b0Image.storeRow(in.y, xs, n, b0s, profile);
                                 momentImages[0]->storeRow(in.y, xs, n, lo, profile);
                                 if (momentImages[1]) momentImages[1]->storeRow(in.y, xs, n, hi, profile);
                               },
                               false, false, {}, true, readsViewDepth);
    }

    const float bias = bias_, overestimation = overestimation_;
    const bool quantised = quantised_;
    static constexpr float kThesisBiasVector[4] = {0.5f, 0.5f, 0.5f, 0.5f};  // Algorithm 5, line 1
    const float* biasVector = set.trigonometric ? nullptr : unitDepth_ ? kThesisBiasVector : powerBiasVector(set.count, quantised);
    const bool saturate = saturate_;
    SpreadCount fallbacks;  // a sum: the same for any order of the fragments
    // The weight e^(−b0·absorbance) of each fragment from the absorbances of the n that
    // reconstruct (used[j] their places in the batch), the others (clear) weighted 1; the
    // exponentials of a batch together (detExpFloatBatch: float(detExp) for each, its series'
    // divisions only where they can change the float).
    auto weightsFrom = [&fallbacks, saturate, driverMath, fused](int count, int n, const int* used, const float* b0s,
                                                                 const float* absorbance, const bool* fellBack, float* w) {
      float weight[kShaderBatch];
      // Each loop on its own, so that each runs in vector lanes (together, GCC ran them a
      // fragment at a time).
      unsigned fell = 0;  // one add per batch, not per fragment that fell back
      for (int j = 0; j < n; ++j) fell += fellBack[j];
      if (fell) fallbacks.add(fell);
      if (driverMath && n > 0) {  // exp(−b0 · absorbance) in fp32 (n > 0: GCC then sees x written)
        float x[kShaderBatch];
        for (int j = 0; j < n; ++j) x[j] = -b0s[j] * absorbance[j];
        llvmpipe::expBatch(x, weight, n, fused);
      } else if (!driverMath && n > 0) {
        double exponent[kShaderBatch];
        for (int j = 0; j < n; ++j) exponent[j] = -double(b0s[j]) * double(absorbance[j]);
        detExpFloatBatch(exponent, weight, n);  // (n > 0: GCC then sees exponent written)
      }
      if (saturate)
        for (int j = 0; j < n; ++j) weight[j] = std::clamp(weight[j], 0.0f, 1.0f);
      if (n == count) {  // then used[j] = j
        std::copy_n(weight, n, w);
        return;
      }
      for (int i = 0; i < count; ++i) w[i] = 1.0f;
      for (int j = 0; j < n; ++j) w[used[j]] = weight[j];
    };
    // A pixel whose b0 is below this has only nearly clear layers: weight 1.
    constexpr float kClearB0 = 0.00100050033f;
    if (usualSet) {
      // The batch's fragments sorted into those that reconstruct and those that are clear
      // without a branch per fragment.
      accumulateWeightedBatch(run, t, accum, reveal, [&](const FragmentBatch& in, const glm::vec4*, float* w) {
        const int count = in.count;
        glm::vec4 loScratch[kShaderBatch];
        float b0Scratch[kShaderBatch];
        const float* b0Texels = redTexelsOf(b0Image, in, b0Scratch);
        const glm::vec4* lo = texelsOf(*momentImages[0], in, loScratch);
        int used[kShaderBatch], n = 0;
        float moments[kShaderBatch * 4], depths[kShaderBatch], absorbance[kShaderBatch], b0s[kShaderBatch];
        bool fellBack[kShaderBatch];
        // Usually every fragment reconstructs (a layer's own absorbance puts its pixel's b0 above
        // kClearB0): then the batch's columns are taken as they are, in lanes.
        bool anyClear = false;
        for (int i = 0; i < count; ++i) b0s[i] = b0Texels[i], anyClear |= b0s[i] < kClearB0;
        if (!anyClear) {
          for (int i = 0; i < count; ++i) depths[i] = linearWarp(in, i), used[i] = i;
          n = count;
        } else {
          for (int i = 0; i < count; ++i) {
            const float b0 = b0Texels[i];
            depths[n] = linearWarp(in, i);
            b0s[n] = b0;
            used[n] = i;
            n += !(b0 < kClearB0);
          }
        }
        normaliseFourMoments(lo, used, b0s, n, moments);
        powerMomentAbsorbanceBatch(4, moments, depths, n, bias, biasVector, overestimation, absorbance, fellBack);
        weightsFrom(count, n, used, b0s, absorbance, fellBack, w);
      }, readsViewDepth);
    } else {
      accumulateWeightedBatch(run, t, accum, reveal, [&](const FragmentBatch& in, const glm::vec4*, float* w) {
        const int count = in.count;
        // The fragments that reconstruct (not clear), their normalised moments and depths side by
        // side, so that the absorbance batches can run them in lanes.
        int used[kShaderBatch], n = 0;
        float moments[kShaderBatch * 8], depths[kShaderBatch], absorbance[kShaderBatch], b0s[kShaderBatch];
        bool fellBack[kShaderBatch];
        // The batch's texels a row at a time (fetchTexels: the layout decided once).
        glm::vec4 loScratch[kShaderBatch], hiScratch[kShaderBatch];
        float b0Scratch[kShaderBatch];
        const float* b0Texels = redTexelsOf(b0Image, in, b0Scratch);
        const glm::vec4* lo = texelsOf(*momentImages[0], in, loScratch);
        const glm::vec4* hi = momentImages[1] ? texelsOf(*momentImages[1], in, hiScratch) : hiScratch;
        for (int i = 0; i < count; ++i) {
          const float b0 = b0Texels[i];
          if (b0 < kClearB0) continue;
          float* b = moments + size_t(n) * size_t(reals);
          if (quantised) {
            float stored[8] = {};
            gatherMoments(lo[i], hi[i], stored);
            dequantiseMoments(set, stored, b);
          } else if (reals > 4) {
            for (int k = 0; k < reals; ++k) b[k] = (k < 4 ? lo[i][k] : hi[i][k - 4]) / b0;
          }
          depths[n] = warp(in, i);
          b0s[n] = b0;
          used[n++] = i;
        }
        // The four moments in fp32 normalised, b_k = m_k / b0, two fragments' in eight lanes.
        if (!quantised && reals == 4) normaliseFourMoments(lo, used, b0s, n, moments);
        if (set.trigonometric)
          trigMomentAbsorbanceBatch(set.count, moments, depths, n, bias, overestimation, zone, absorbance, fellBack);
        else
          powerMomentAbsorbanceBatch(set.count, moments, depths, n, bias, biasVector, overestimation, absorbance, fellBack);
        weightsFrom(count, n, used, b0s, absorbance, fellBack, w);
      }, readsViewDepth);
    }

    compositeWeighted(run, t, accum, reveal, clamp_);  // as WBOIT
    result.stats.momentFallbacks = fallbacks.total();
  }

 private:
  std::string momentRange(int from, int to) const {
    if (set_.trigonometric)
      return "Σ A·(cos kφ, sin kφ), k = " + std::to_string(from / 2 + 1) + "…" + std::to_string(to / 2);
    return "Σ A·z^k, k = " + std::to_string(from + 1) + "…" + std::to_string(to);
  }

  MomentSet set_;
  bool quantised_;
  float bias_, overestimation_;
  bool logWarp_, unitDepth_, saturate_;
  ResolveClamp clamp_;
  ColorHandle b0_, moments_, momentsMore_, accum_, reveal_;  // momentsMore_: more than four moments
};

}  // namespace

const MethodInfo& mboitInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "mboit",
      "moment-based OIT: 4/6/8 power or 2/3/4 trigonometric moments, fp32 or 16-bit (Münstermann et al. 2018; thesis Algorithms 5–6)",
      {{"moments", "power4", "moment set: power moments of z, or trigonometric moments of its phase",
        {"power4", "power6", "power8", "trig2", "trig3", "trig4"}},
       {"storage", "float", "moments in fp32 targets blended additively, or normalised and quantised into UNORM16", {"float", "unorm16"}},
       {"bias", "auto", "moment bias β (auto: the published value for the moment set and storage; the thesis used 0)", {},
        OptionNumber::real(0, 1, true)},
       {"overestimation", "0.25", "weight of the fragment's own depth in the absorbance", {}, OptionNumber::real(0, 1)},
       {"warp", "linear",
        "depth into [−1, 1]: linear 2d − 1 (window depth) or log of the view depth; unit: the window depth d in [0, 1] with "
        "the bias vector (0.5, 0.5, 0.5, 0.5), as thesis Algorithms 5–6 (power4, float only)",
        {"linear", "log", "unit"}},
       {"saturate", "auto", "T = exp(−b0·a) clamped to [0, 1] for power moments as the paper's code does (auto; trigonometric: never), or never as thesis eq. 2.11 prints it (none)",
        {"auto", "none"}},
       {"clamp", "mb", "the composite's divisor Σα·w: clamped to [1e-4, 5e4] (mb, as WBOIT) or as it is (none, thesis eq. 2.9 with eq. 2.7)", {"mb", "none"}},
       {"accum", "rgba32f", "accumulation format (thesis: RGBA32F)", {"rgba16f", "rgba32f"}}},
      {{"thesis", "Algorithms 5–6 as printed: four power moments of the depth in [0, 1], Hamburger4MSM with bias 0 (vector 0.5) "
                  "and its lower bound (overestimation 0), T = exp(−a·S) unclamped, eq. 2.7 unclamped, RGBA32F/R32F",
        {{"moments", "power4"}, {"storage", "float"}, {"bias", "0"}, {"overestimation", "0"}, {"warp", "unit"},
         {"saturate", "none"}, {"clamp", "none"}, {"accum", "rgba32f"}}}}};
    i.studyVariants = {
        {{"preset", "thesis"}},
        {{"bias", "0"}},
        {{"warp", "log"}},
        {{"accum", "rgba16f"}},
        {{"moments", "power6"}},
        {{"moments", "power8"}},
        {{"moments", "trig2"}},
        {{"moments", "trig3"}},
        {{"moments", "trig4"}},
        // 16-bit quantised moments with the published biases (bias=auto).
        {{"storage", "unorm16"}},
        {{"moments", "power6"}, {"storage", "unorm16"}},
        {{"moments", "power8"}, {"storage", "unorm16"}},
        {{"moments", "trig2"}, {"storage", "unorm16"}}};
    i.stressVariants = {{},
                        {{"accum", "rgba16f"}},
                        {{"warp", "log"}},
                        {{"moments", "power8"}},
                        {{"moments", "trig3"}},
                        {{"storage", "unorm16"}}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> mboitFactory(const MethodOptions& o) { return std::make_unique<Mboit>(o); }

}  // namespace oitref::methods
