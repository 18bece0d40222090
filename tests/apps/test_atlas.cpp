// The stability atlas (oitref stress): its exact reference checked against both ground truths,
// and every numeric failure the atlas found (docs/atlas.md) asserted as documented behaviour,
// each with the derivation that predicts it.
#include <catch2/catch.hpp>
#include <cmath>

#include "oitref/core/renderer.h"
#include "tools/stress.h"

using namespace oitref;
using namespace oitref::tools;

namespace {

StressCondition condition(const std::string& name) {
  for (const StressCondition& c : stressConditions())
    if (c.name == name) return c;
  FAIL("no condition " << name);
  return {};
}

Renderer& renderer() {
  static Renderer r(RendererOptions{2, 64});
  return r;
}

StressCell cell(const std::string& method, std::map<std::string, std::string> options, const std::string& cond, int n,
                float alpha) {
  return stressCell({method, std::move(options)}, condition(cond), n, alpha, 4, renderer());
}

}  // namespace

TEST_CASE("Atlas: the exact reference equals the A-buffer in double and the ray cast", "[atlas]") {
  for (const char* cond : {"base", "colocated", "wide", "hdr"})
    for (int n : {1, 2, 7, 64})
      for (float alpha : {0.0f, 1e-4f, 0.5f, 0.99f, 1.0f}) {
        INFO(cond << " n=" << n << " alpha=" << alpha);
        const StressCell a = cell("abuffer", {{"precision", "double"}}, cond, n, alpha);
        CHECK(a.error < 1e-6 * (cond == std::string("hdr") ? 16 : 1));
        CHECK(a.nonFinitePixels == 0);
        const StressCell r = cell("raycast", {}, cond, n, alpha);
        CHECK(r.error < 1e-6 * (cond == std::string("hdr") ? 16 : 1));
      }
}

TEST_CASE("Atlas: WBOIT with McGuire–Bavoil's eq. 7 in RGBA16F overflows where Σα·w passes 65520", "[atlas]") {
  // accum.a = Σ α·w_i with w = α·clamp(10 / (1e-5 + (z/5)² + (z/200)⁶), 1e-2, 3e3) (the paper's
  // eq. 7), z the view distance of layer i: first·(last/first)^(i/(n−1)) times the scene's
  // scale. An RGBA16F channel becomes inf once the running sum reaches 65520 (half of the step
  // above 65504). The colour channels carry c·α·w; with c ≤ 1 the alpha channel is the largest,
  // with HDR colours (× 16) the red channel of the red layers is. Predict the largest channel's
  // sum in double; away from the threshold (±5 %) the render must agree.
  const float alpha = 0.9f;
  int overflowing = 0, finite = 0;
  for (const char* name : {"base", "wide", "scaled_x0.01", "hdr"}) {
    const StressCondition c = condition(name);
    for (int n : kStressLayers) {
      double sumAlpha = 0, sumRed = 0;
      for (int i = 0; i < n; ++i) {
        const double t = n > 1 ? double(i) / (n - 1) : 0.0;
        const double z = double(c.firstDistance) * std::pow(double(c.lastDistance) / double(c.firstDistance), t) * c.sceneScale;
        const double w = alpha * std::clamp(10.0 / (1e-5 + std::pow(z / 5, 2) + std::pow(z / 200, 6)), 1e-2, 3e3);
        sumAlpha += alpha * w;
        sumRed += (i % 2 ? 0.1 : 1.0) * c.colourScale * alpha * w;  // the layers alternate red and blue
      }
      const double largest = std::max(sumAlpha, sumRed);
      if (largest > 0.95 * 65520 && largest < 1.05 * 65520) continue;
      INFO(name << " n=" << n << ": predicted largest channel sum " << largest);
      const StressCell got = cell("wboit", {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}}, name, n, alpha);
      const bool inf = std::find(got.infIn.begin(), got.infIn.end(), "accum") != got.infIn.end();
      CHECK(inf == (largest >= 65520));
      (inf ? overflowing : finite)++;
    }
  }
  CHECK(overflowing >= 4);
  CHECK(finite >= 20);
  // The atlas's findings, by condition: the first layer count of the sweep with inf in accum.
  // A scene 100 times smaller overflows 64 times sooner: eq. 7 is not scale-invariant.
  CHECK(cell("wboit", {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}}, "base", 1024, alpha).infIn.empty());
  CHECK(!cell("wboit", {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}}, "base", 2048, alpha).infIn.empty());
  CHECK(cell("wboit", {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}}, "scaled_x0.01", 16, alpha).infIn.empty());
  CHECK(!cell("wboit", {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}}, "scaled_x0.01", 32, alpha).infIn.empty());
  // inf in accum reaches the image as NaN (inf / inf in the resolve) one step later.
  CHECK(cell("wboit", {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}}, "scaled_x0.01", 64, alpha).nonFinitePixels > 0);
}

TEST_CASE("Atlas: MBOIT goes black behind many opaque layers", "[atlas]") {
  // α = 1 is clamped to 1 − 2^-20, so every layer adds A = 20·ln 2 = 13.86 to b0 = n·13.86. The
  // front layer's weight is w = exp(−b0·a), a its reconstructed absorbance; any excess ε of a
  // over the truth costs exp(−13.86·n·ε), and the resolve divides Σ c·α·w by max(Σ α·w, 1e-4):
  // once the front layer's w falls well below 1e-4 the colour collapses to black, although the
  // exact result is simply the front layer's colour. Spread layers: exact through 32 layers,
  // black from 64 (a cliff, not a slope).
  for (int n : {1, 2, 4, 8, 16, 32}) {
    INFO("n=" << n);
    CHECK(cell("mboit", {}, "base", n, 1.0f).error < 0.01);
  }
  CHECK(cell("mboit", {}, "base", 64, 1.0f).error > 0.9);
  // Co-located layers share one depth: each gets the same weight, a single layer's being the
  // overestimation 0.25 of all of b0. Two layers average red (1, 0.2, 0.1) and blue
  // (0.1, 0.4, 1) where the exact result is the front one: an error of (1 − 0.1)/2 = 0.45 in
  // red; from 4 layers w = exp(−0.25·4·13.86) = 9.6e-7 and the image is nearly black.
  CHECK(cell("mboit", {}, "colocated", 2, 1.0f).error == Approx(0.45).margin(1e-4));
  CHECK(cell("mboit", {}, "colocated", 4, 1.0f).error > 0.95);
}

TEST_CASE("Atlas: MBOIT's moments of co-located layers stop being positive definite in fp32", "[atlas]") {
  // Layers at one depth z have moments (z, z², z³, z⁴): a point mass, whose Hankel matrix is
  // singular. Only the bias β = 5e-7 keeps it positive definite, by about β relative to the
  // moments — a few fp32 ulps. Summing n equal contributions in fp32 (b0 and the moments
  // separately, then dividing) adds rounding of order n·ulp, which wins from some n on; the
  // reconstruction then falls back to the fragment's own layer. The log warp maps distance 5 to
  // a z nearer 0, where the moments are smaller and the sums exact for longer.
  for (int n : {1, 2, 4, 8}) CHECK(cell("mboit", {}, "colocated", n, 1e-4f).momentFallbacks == 0);
  CHECK(cell("mboit", {}, "colocated", 16, 1e-4f).momentFallbacks > 0);
  CHECK(cell("mboit", {{"warp", "log"}}, "colocated", 512, 1e-4f).momentFallbacks == 0);
  CHECK(cell("mboit", {{"warp", "log"}}, "colocated", 1024, 1e-4f).momentFallbacks > 0);
}

TEST_CASE("Atlas: weighted average's layer count stalls where the format's step passes 1", "[atlas]") {
  // count += 1 per layer, blended ONE, ONE into r16f: from 2048 on fp16's step is 2, and
  // 2048 + 1 is a tie that rounds to even, 2048. In bfloat16 (r:e8m7) the step is 2 from 256 on.
  for (const auto& [format, stall] : {std::pair<std::string, float>{"rgba16f", 2048.0f}, {"rgba:e8m7", 256.0f}}) {
    const Scene scene = stressScene(condition("base"), 4096, 0.5f, 2, 2);
    const SceneGeometry geometry = buildSceneGeometry(scene);
    const FrameContext context{scene, geometry, 2, 2, exactProfile(), renderer()};
    const FrameResult frame = makeMethod("wavg", {{"accum", format}})->render(context);
    const auto count = std::find_if(frame.dump.begin(), frame.dump.end(), [](const auto& d) { return d.first == "count"; });
    REQUIRE(count != frame.dump.end());
    CHECK(count->second.fetch(0, 0).r == stall);
  }
}

TEST_CASE("Atlas: every failure of docs/atlas.md starts where the atlas says", "[atlas]") {
  // The table of docs/atlas.md ("where each failure starts"): at `first` layers the failure is
  // there, at first/2 (same α) it is not.
  struct Finding {
    const char* condition;
    const char* method;
    std::map<std::string, std::string> options;
    const char* what;  // "inf", "nonfinite", "fallback"
    int first;
    float alpha;
  };
  const std::map<std::string, std::string> mb7 = {{"accum", "rgba16f"}, {"reveal", "r8"}, {"weight", "mb7"}};
  const std::vector<Finding> findings = {
      {"base", "wboit", mb7, "inf", 2048, 0.9f},          {"base", "wboit", mb7, "nonfinite", 4096, 0.9f},
      {"wide", "wboit", mb7, "inf", 128, 0.9f},           {"wide", "wboit", mb7, "nonfinite", 256, 0.9f},
      {"scaled_x0.01", "wboit", mb7, "inf", 32, 0.9f},    {"scaled_x0.01", "wboit", mb7, "nonfinite", 64, 0.9f},
      {"hdr", "wboit", mb7, "inf", 256, 0.9f},            {"hdr", "wboit", mb7, "nonfinite", 256, 0.9f},
      {"bright", "wboit", mb7, "inf", 2048, 0.9f},        {"bright", "wboit", mb7, "nonfinite", 4096, 0.9f},
      {"base", "mboit", {}, "fallback", 2048, 1e-4f},     {"colocated", "mboit", {}, "fallback", 16, 1e-4f},
      {"colocated", "mboit", {{"warp", "log"}}, "fallback", 1024, 1e-4f},
      {"wide", "mboit", {}, "fallback", 1024, 0.9f},      {"distant", "mboit", {}, "fallback", 16, 0.1f},
      {"scaled_x100", "mboit", {}, "fallback", 1024, 1e-4f},
      {"scaled_x0.01", "mboit", {}, "fallback", 2048, 1e-4f},
      {"hdr", "mboit", {}, "fallback", 2048, 1e-4f},      {"bright", "mboit", {}, "fallback", 2048, 1e-4f},
      {"base", "mboit", {{"moments", "trig3"}}, "fallback", 128, 1.0f},
      {"colocated", "mboit", {{"moments", "power8"}}, "fallback", 32, 1e-4f},
      {"base", "mboit", {{"storage", "unorm16"}}, "fallback", 256, 1e-4f},
      {"distant", "mboit", {{"storage", "unorm16"}}, "fallback", 8, 0.01f},
      {"colocated", "mt", {}, "fallback", 8, 1e-4f},
      {"hdr", "meshkin3", {}, "inf:t3", 8, 0.5f},
  };
  auto shows = [](const StressCell& c, const std::string& what) {
    if (what == "inf") return std::find(c.infIn.begin(), c.infIn.end(), "accum") != c.infIn.end();
    if (what.rfind("inf:", 0) == 0) return std::find(c.infIn.begin(), c.infIn.end(), what.substr(4)) != c.infIn.end();
    if (what == "nonfinite") return c.nonFinitePixels > 0;
    return c.momentFallbacks > 0;
  };
  for (const Finding& f : findings) {
    INFO(f.condition << " " << f.method << " " << f.what << " from n=" << f.first << " at alpha=" << f.alpha);
    CHECK(shows(cell(f.method, f.options, f.condition, f.first, f.alpha), f.what));
    CHECK(!shows(cell(f.method, f.options, f.condition, f.first / 2, f.alpha), f.what));
  }
}

TEST_CASE("Atlas: meshkin3's 1/α overflows RGBA16F below α = 1/65520", "[atlas]") {
  // t2 sums 1/α: α = 0 stores inf, which the composite multiplies by t3.a = Πα = 0 (NaN); any
  // α < 1/65520 stores inf too (fp16's largest finite value is 65504), and inf·Πα stays inf.
  for (float alpha : {0.0f, 1e-7f}) {
    const StressCell c = cell("meshkin3", {}, "base", 1, alpha);
    CHECK(c.nonFinitePixels > 0);
    CHECK(std::find(c.infIn.begin(), c.infIn.end(), "t2") != c.infIn.end());
  }
  CHECK(cell("meshkin3", {}, "base", 1, 1e-4f).nonFinitePixels == 0);  // 1/α = 10000 fits
  CHECK(cell("meshkin3", {{"format", "rgba32f"}}, "base", 1, 1e-7f).nonFinitePixels == 0);
}

TEST_CASE("Atlas: DFAOIT cannot add more than 1 per channel: HDR layers are clipped", "[atlas]") {
  // The network ends in a sigmoid (the paper's architecture): the transparent colour it adds
  // is below 1 in every channel, so HDR layers (colours × 16) lose almost all their energy;
  // up to two layers the method composites exactly and has no such limit.
  CHECK(cell("dfaoit", {}, "hdr", 2, 0.5f).error < 1e-3);
  const StressCell four = cell("dfaoit", {}, "hdr", 4, 0.5f);
  CHECK(four.error > 9);
  CHECK(four.nonFinitePixels == 0);
  // The same scene in [0, 1] colours stays within the method's ordinary error.
  CHECK(cell("dfaoit", {}, "base", 4, 0.5f).error < 0.1);
}
