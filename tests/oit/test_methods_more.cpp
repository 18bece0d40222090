// The methods beyond the thesis's five, each against a closed form over the A-buffer's fragment
// lists (method_fixture.h), evaluated independently of the method's code.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include "method_fixture.h"
#include "methods/dfaoit_network.h"
#include "methods/methods.h"
#include "oitref/core/depth.h"
#include "support.h"
#include "util/seeded_random.h"

using namespace oitref;
using namespace oitref::test;

TEST_CASE("screendoor: the Bayer matrices are the published ones and permutations", "[methods][screendoor]") {
  // Bayer 4×4 as printed in the literature, rows y = 0..3.
  const uint32_t b4[4][4] = {{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}};
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) CHECK(methods::bayerIndex(4, x, y) == b4[y][x]);
  for (int n : {2, 4, 8}) {
    std::set<uint32_t> values;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) values.insert(methods::bayerIndex(n, x + 3 * n, y + 5 * n));  // periodic
    CHECK(values.size() == size_t(n * n));
    CHECK(*values.rbegin() == uint32_t(n * n - 1));
  }
}

TEST_CASE("screendoor: each pixel shows the nearest fragment whose α passes its threshold", "[methods][screendoor]") {
  for (int n : {2, 4, 8}) {
    const FrameResult sd = render(reference().scene, "screendoor", {{"mask", std::to_string(n)}});
    forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
      // Depth test LESS in d24: the first fragment (submission order) with the smallest encoded
      // depth among those that survive the mask.
      const TransparentFragment* front = nullptr;
      uint32_t frontDepth = 0;
      for (const TransparentFragment& fr : f) {
        // The threshold from the Bayer matrix written out for n = 2, 4, 8 by the recursion's
        // closed form: B(x, y) = Σ_k 4^(levels−1−k)·q(bit k of x, bit k of y), q = (0 2; 3 1).
        uint32_t b = 0;
        for (int bit = 0, weight = n * n / 4; (1 << bit) < n; ++bit, weight /= 4) {
          const int bx = (x >> bit) & 1, by = (y >> bit) & 1;
          b += uint32_t(weight) * (by ? (bx ? 1u : 3u) : (bx ? 2u : 0u));
        }
        if (!(double(fr.color.a) > (b + 0.5) / (n * n))) continue;
        const uint32_t d = encodeDepth(fr.windowDepth, DepthFormat::D24);
        if (!front || d < frontDepth) front = &fr, frontDepth = d;
      }
      const glm::dvec3 want = front ? glm::dvec3(glm::vec3(front->color)) : c0;
      requireClose(sd.finalFloat, x, y, want, 0.0, "screendoor");
    });
  }
}

TEST_CASE("screendoor: a layer of α = k/N² covers k pixels of every tile", "[methods][screendoor]") {
  Scene s = layerScene(16, {0, 0, 0});
  for (int k : {0, 1, 5, 8, 15, 16}) {
    s.objects = {quad({0, 0, 0}, 10, {1, 1, 1, float(k) / 16.0f})};
    s.objects[0].transparentOverride = true;
    const FrameResult sd = render(s, "screendoor");
    for (int ty = 0; ty < 16; ty += 4)
      for (int tx = 0; tx < 16; tx += 4) {
        int covered = 0;
        for (int y = ty; y < ty + 4; ++y)
          for (int x = tx; x < tx + 4; ++x) covered += sd.finalFloat.fetch(x, y).r == 1.0f;
        CHECK(covered == k);
      }
  }
}

TEST_CASE("wboit layout=single (listing 4) is eq. 2.5 with the revealage in accum's alpha", "[methods][wboit]") {
  for (const char* accum : {"rgba32f", "rgba16f"}) {
    const double u = std::string(accum) == "rgba16f" ? kU16 : kU32;
    const FrameResult wb = render(reference().scene, "wboit", {{"layout", "single"}, {"accum", accum}, {"weight", "az3"}});
    forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
      glm::dvec3 sum(0.0);
      double weights = 0, reveal = 1, largest = 0;
      for (const auto& fr : f) {
        const double w = fr.color.a / std::pow(double(fr.windowDepth), 3);
        sum += glm::dvec3(glm::vec3(fr.color)) * double(fr.color.a) * w;
        weights += fr.color.a * w;
        reveal *= 1.0 - fr.color.a;
        largest = std::max(largest, weights);
      }
      const glm::dvec3 want = f.empty() ? c0 : sum / std::clamp(weights, 1e-4, 5e4) * (1 - reveal) + c0 * reveal;
      // The sums and the product round in the accumulation format; the ratio of two sums with
      // relative error (n + 4)·u each is within 2·(n + 4)·u of the true ratio (colours ≤ 1).
      const double bound = 8 * (f.size() + 4) * u * (1 + largest / std::max(weights, 1e-4));
      requireClose(wb.finalFloat, x, y, want, bound, accum);
    });
    // The same bits as listing 3 in fp32, where both keep the revealage in fp32.
    if (std::string(accum) == "rgba32f") {
      const FrameResult mrt = render(reference().scene, "wboit", {{"accum", accum}, {"weight", "az3"}});
      CHECK(mrt.finalFloat.sameBits(wb.finalFloat));
    }
  }
}

namespace {

// Bavoil–Myers over the given layers onto c0, in double: (avg·(1 − T) + c0·T).
glm::dvec3 weightedAverageOnto(const std::vector<TransparentFragment>& layers, const glm::dvec3& c0) {
  if (layers.empty()) return c0;
  glm::dvec3 sum(0.0);
  double alpha = 0;
  for (const auto& f : layers) sum += glm::dvec3(glm::vec3(f.color)) * double(f.color.a), alpha += f.color.a;
  const double n = double(layers.size()), t = std::pow(std::max(0.0, 1.0 - alpha / n), n);
  return sum / std::max(alpha, 1e-4) * (1.0 - t) + c0 * t;
}

}  // namespace

TEST_CASE("hybrid: the k nearest fragments exactly over the others' weighted average", "[methods][hybrid]") {
  struct Case {
    int k;
    const char *core, *tail;
  };
  for (const Case& c : {Case{2, "rgba32f", "rgba32f"}, Case{4, "rgba32f", "rgba16f"}, Case{8, "rgba32f", "rgba16f"},
                        Case{4, "rgba8", "rgba32f"}}) {
    const FrameResult hy = render(reference().scene, "hybrid", {{"k", std::to_string(c.k)}, {"core", c.core}, {"tail", c.tail}});
    const double u = std::string(c.tail) == "rgba16f" ? kU16 : kU32;
    forEachPixel([&](int x, int y, std::vector<TransparentFragment> f, glm::dvec3 c0) {
      // Front to back by window depth; equal depths keep submission order (earlier in front).
      std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.windowDepth < b.windowDepth; });
      const size_t core = std::min(f.size(), size_t(c.k));
      const std::vector<TransparentFragment> tail(f.begin() + std::ptrdiff_t(core), f.end());
      glm::dvec3 want = weightedAverageOnto(tail, c0);
      for (size_t i = core; i-- > 0;) want = glm::dvec3(glm::vec3(f[i].color)) * double(f[i].color.a) + want * (1.0 - f[i].color.a);
      double alpha = 0;
      for (const auto& fr : tail) alpha += fr.color.a;
      const double n = double(tail.size());
      // The tail as the weighted-average test bounds it; core colours in RGBA8 are off by at
      // most half a step each, which the OVER chain passes on at most once in total (weights
      // α_i·Π(1 − α_j) sum to ≤ 1); evicted fragments reach the tail in that format too.
      // The average's error is scaled by the tail's opacity 1 − T ≤ Σα.
      double bound = 4 * (n + 2) * u * (1 + alpha) + 4 * n * (n + 2) * u + 16 * kU32 * (core + 2);
      if (std::string(c.core) == "rgba8") bound += 2.0 / 255;
      requireClose(hy.finalFloat, x, y, want, bound, c.core);
    });
  }
}

TEST_CASE("hybrid: with k at least the depth complexity it is the exact composite", "[methods][hybrid]") {
  const FrameResult hy = render(reference().scene, "hybrid", {{"k", "16"}});
  size_t deepest = 0;
  forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
    deepest = std::max(deepest, f.size());
    requireClose(hy.finalFloat, x, y, overBackToFront(f, c0), 4 * (f.size() + 2) * kU32 * 2, "hybrid k=16");
  });
  REQUIRE(deepest <= 16);
  // And the split matters: with k = 2, pixels deeper than 2 are off the exact composite.
  const FrameResult k2 = render(reference().scene, "hybrid", {{"k", "2"}});
  int off = 0;
  forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
    const glm::dvec3 exact = overBackToFront(f, c0);
    const glm::vec4 got = k2.finalFloat.fetch(x, y);
    if (f.size() > 2 && std::abs(got.r - exact.r) + std::abs(got.g - exact.g) + std::abs(got.b - exact.b) > 1e-3) ++off;
  });
  CHECK(off > 20);
}

TEST_CASE("dualpeel: with enough passes it is the exact composite wherever depths do not tie", "[methods][dualpeel]") {
  const FrameResult dp = render(reference().scene, "dualpeel", {{"color", "rgba32f"}});
  int tied = 0, checked = 0;
  forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
    std::set<float> depths;
    for (const auto& fr : f) depths.insert(fr.windowDepth);
    if (depths.size() != f.size()) return void(++tied);  // collisions: the next test
    ++checked;
    // Front layers accumulate under in fp32, back layers OVER in fp32: a few roundings per layer.
    requireClose(dp.finalFloat, x, y, overBackToFront(f, c0), 8 * (f.size() + 2) * kU32 * 2, "dualpeel");
  });
  CHECK(checked > 3000);
  CHECK(tied < checked / 100);
  // The loop ends after the first pass k whose back-blend pass draws nothing (the sample's
  // occlusion query): no pixel has a back layer then — the k-th from the back of a pixel with at
  // least 2k layers — of α ≠ 0. Without fully transparent fragments that is pass ⌈N/2⌉ + 1 for the
  // deepest pixel's N; the textured quads' α = 0 texels can end it sooner.
  size_t expected = 0;
  for (size_t k = 1; expected == 0; ++k) {
    bool drawn = false;
    forEachPixel([&](int, int, std::vector<TransparentFragment> f, glm::dvec3) {
      if (f.size() < 2 * k) return;
      std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.windowDepth < b.windowDepth; });
      drawn = drawn || f[f.size() - k].color.a != 0.0f;
    });
    if (!drawn) expected = k;
  }
  size_t deepest = 0;
  forEachPixel([&](int, int, const std::vector<TransparentFragment>& f, glm::dvec3) { deepest = std::max(deepest, f.size()); });
  CHECK(expected <= (deepest + 1) / 2 + 1);
  CHECK(dp.stats.peelingPasses == int(expected));
  CHECK(dp.stats.allLayersPeeled == true);
}

TEST_CASE("dualpeel: two layers at exactly the same depth collide under MAX", "[methods][dualpeel]") {
  // Red and blue, α = 0.5, coplanar, over a black background. Both are the nearest layer of the
  // first pass, so both write front = (c·α, α) and MAX keeps the component-wise maximum:
  // (0.5, 0, 0.5) with coverage 0.5 — a colour neither order gives. The exact composite (either
  // ground truth: the earlier submission in front) is red over blue: (0.5, 0, 0.25).
  Scene s = layerScene(8, {0, 0, 0});
  s.objects = {quad({0, 0, 0}, 10, {1, 0, 0, 0.5f}), quad({0, 0, 0}, 10, {0, 0, 1, 0.5f})};
  const glm::vec4 dual = render(s, "dualpeel", {{"color", "rgba32f"}}).finalFloat.fetch(4, 4);
  CHECK(dual.r == 0.5f);
  CHECK(dual.g == 0.0f);
  CHECK(dual.b == 0.5f);
  const glm::vec4 exact = render(s, "abuffer").finalFloat.fetch(4, 4);
  CHECK(exact.r == 0.5f);
  CHECK(exact.b == 0.25f);
}

TEST_CASE("stochastic: masks have round(α·S) bits, differ between fragments, repeat exactly", "[methods][stochastic]") {
  for (int s : {8, 16, 32})
    for (float a : {0.0f, 0.03f, 0.45f, 0.5f, 0.97f, 1.0f}) {
      const int want = int(std::floor(double(a) * s + 0.5));
      std::set<uint32_t> distinct;
      for (int x = 0; x < 20; ++x) {
        const uint32_t m = methods::stochasticMask(7, x, 3, 2, 5, a, s);
        CHECK(__builtin_popcount(m) == want);
        CHECK((s == 32 || m >> s == 0));
        CHECK(m == methods::stochasticMask(7, x, 3, 2, 5, a, s));
        distinct.insert(m);
      }
      if (want > 0 && want < s) CHECK(distinct.size() > 10);
    }
}

TEST_CASE("stochastic: a mask is the first round(α·S) entries of a Fisher–Yates shuffle of the samples",
          "[methods][stochastic]") {
  // The oracle: the shuffle as the textbook writes it (every entry filled, then swapped), driven by
  // the same generator from the fragment's key.
  test::BitStream rng(5);
  for (int i = 0; i < 3000; ++i) {
    const int samples = i % 3 == 0 ? 8 : i % 3 == 1 ? 16 : 32;
    const float alpha = rng.uniform(0.0f, 1.0f);
    const uint32_t seed = uint32_t(rng.next()), object = uint32_t(rng.next() % 50), primitive = uint32_t(rng.next());
    const int x = int(rng.next() % 4096), y = int(rng.next() % 4096);
    uint64_t state = methods::stochasticFragmentKey(seed, x, y, object, primitive);
    util::splitMix64(state);
    std::vector<int> order(static_cast<size_t>(samples));
    for (int k = 0; k < samples; ++k) order[size_t(k)] = k;
    const int bits = std::clamp(int(std::floor(double(alpha) * samples + 0.5)), 0, samples);
    uint32_t want = 0;
    for (int k = 0; k < bits; ++k) {
      const int j = k + int(util::splitMix64(state) % uint64_t(samples - k));
      std::swap(order[size_t(k)], order[size_t(j)]);
      want |= 1u << order[size_t(k)];
    }
    INFO("samples " << samples << " alpha " << alpha);
    REQUIRE(methods::stochasticMask(seed, x, y, object, primitive, alpha, samples) == want);
  }
}

TEST_CASE("stochastic: red over green over blue, the paper's example", "[methods][stochastic]") {
  // Red in front, green behind, α = 0.45 each, blue background. Red passes LEQUAL in every
  // sample (nothing is in front of it): v = 1. Green fails exactly where red is stored, in the
  // k = round(0.45·S) samples of red's mask: v = 1 − k/S, whatever the random bits. With the
  // exact revealage T = 0.55² = 0.3025 the corrected colour is
  //   (0.45, 0.45·(1 − k/S), 0) / (0.45·(2 − k/S)) · (1 − T) + (0, 0, 1)·T,
  // which tends to the paper's (0.45, 0.2475, 0.3025) as k/S → α.
  Scene s = layerScene(8, {0, 0, 1});
  s.objects = {quad({0, 0, -1}, 10, {0, 1, 0, 0.45f}), quad({0, 0, 0}, 10, {1, 0, 0, 0.45f})};
  for (int samples : {8, 16, 32}) {
    const double k = std::floor(0.45 * samples + 0.5), vGreen = 1 - k / samples, t = 0.55 * 0.55;
    const double a = 0.45 * (1 + vGreen);
    const glm::dvec3 want(0.45 / a * (1 - t), 0.45 * vGreen / a * (1 - t), t);
    for (const char* seed : {"1", "2"}) {
      const FrameResult st = render(s, "stochastic", {{"samples", std::to_string(samples)}, {"seed", seed}, {"accum", "rgba32f"}});
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) requireClose(st.finalFloat, x, y, want, 1e-6, "stochastic");
    }
  }
  // S = 32: within 0.004 of the paper's expectation (k/S = 0.4375 for α = 0.45).
  const glm::vec4 s32 = render(s, "stochastic", {{"samples", "32"}}).finalFloat.fetch(4, 4);
  CHECK(s32.r == Approx(0.45).margin(4e-3));
  CHECK(s32.g == Approx(0.2475).margin(4e-3));
  CHECK(s32.b == Approx(0.3025).margin(1e-3));
}

TEST_CASE("stochastic: the error shrinks toward the A-buffer as S grows", "[methods][stochastic]") {
  auto meanRmse = [](int samples) {
    double sum = 0;
    for (int seed = 1; seed <= 3; ++seed) {
      const FrameResult st = render(reference().scene, "stochastic",
                                    {{"samples", std::to_string(samples)}, {"seed", std::to_string(seed)}});
      double squares = 0;
      forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
        const glm::dvec3 d = glm::dvec3(glm::vec3(st.finalFloat.fetch(x, y))) - overBackToFront(f, c0);
        squares += glm::dot(d, d);
      });
      sum += std::sqrt(squares / (3.0 * reference().scene.width * reference().scene.height));
    }
    return sum / 3;
  };
  const double e8 = meanRmse(8), e16 = meanRmse(16), e32 = meanRmse(32);
  INFO("mean RMSE over 3 seeds: S=8 " << e8 << ", S=16 " << e16 << ", S=32 " << e32);
  CHECK(e16 < e8);
  CHECK(e32 < e16);
}

TEST_CASE("kbuffer: the k nearest fragments composited exactly, the rest dropped", "[methods][kbuffer]") {
  for (int k : {1, 2, 4}) {
    const FrameResult kb = render(reference().scene, "kbuffer", {{"k", std::to_string(k)}});
    forEachPixel([&](int x, int y, std::vector<TransparentFragment> f, glm::dvec3 c0) {
      std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.windowDepth < b.windowDepth; });
      if (f.size() > size_t(k)) f.resize(size_t(k));
      glm::dvec3 want = c0;
      for (size_t i = f.size(); i-- > 0;) want = glm::dvec3(glm::vec3(f[i].color)) * double(f[i].color.a) + want * (1.0 - f[i].color.a);
      requireClose(kb.finalFloat, x, y, want, 8 * (f.size() + 2) * kU32, "kbuffer");
    });
  }
}

TEST_CASE("mlab: exact with enough nodes, and merges keep the total transmittance exactly", "[methods][mlab]") {
  const FrameResult full = render(reference().scene, "mlab", {{"k", "16"}});
  forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
    requireClose(full.finalFloat, x, y, overBackToFront(f, c0), 8 * (f.size() + 2) * kU32, "mlab k=16");
  });
  // The composite is Σ(colour terms) + C0·Π T; merging multiplies transmittances, so Π T is
  // Π(1 − α) whatever merged. Two backgrounds, same layers: the difference of the results is
  // (C0a − C0b)·Π(1 − α), independent of the merge order.
  Scene a = reference().scene, b = reference().scene;
  b.background = {0.9f, 0.1f, 0.6f};
  Scene aOnly = a, bOnly = b;
  std::erase_if(aOnly.objects, [](const SceneObject& o) { return o.isTransparent(); });
  std::erase_if(bOnly.objects, [](const SceneObject& o) { return o.isTransparent(); });
  const Image c0a = render(aOnly, "over").finalFloat, c0b = render(bOnly, "over").finalFloat;
  for (const char* k : {"1", "2"}) {
    const Image ra = render(a, "mlab", {{"k", k}}).finalFloat, rb = render(b, "mlab", {{"k", k}}).finalFloat;
    int merged = 0;
    forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3) {
      double t = 1;
      for (const auto& fr : f) t *= 1.0 - fr.color.a;
      merged += f.size() > size_t(std::stoi(k));
      const glm::dvec3 diff = glm::dvec3(glm::vec3(ra.fetch(x, y))) - glm::dvec3(glm::vec3(rb.fetch(x, y)));
      const glm::dvec3 want = (glm::dvec3(glm::vec3(c0a.fetch(x, y))) - glm::dvec3(glm::vec3(c0b.fetch(x, y)))) * t;
      for (int c = 0; c < 3; ++c)
        if (!(std::abs(diff[c] - want[c]) <= 8 * (f.size() + 2) * kU32 * 2))
          FAIL("mlab k=" << k << " pixel " << x << "," << y << ": background term " << diff[c] << ", Π(1 − α) says " << want[c]);
    });
    CHECK(merged > 100);
  }
  // Merging two depth-adjacent nodes is OVER: two layers with k = 1 are exact whatever the order.
  Scene two = layerScene(4, {0, 0, 1});
  for (bool frontFirst : {true, false}) {
    two.objects = {quad({0, 0, 0}, 10, {1, 0, 0, 0.3f}), quad({0, 0, -1}, 10, {0, 1, 0, 0.6f})};
    if (!frontFirst) std::swap(two.objects[0], two.objects[1]);
    const glm::vec4 got = render(two, "mlab", {{"k", "1"}}).finalFloat.fetch(2, 2);
    CHECK(got.r == Approx(0.3).margin(1e-6));
    CHECK(got.g == Approx(0.7 * 0.6).margin(1e-6));
    CHECK(got.b == Approx(0.7 * 0.4).margin(1e-6));
  }
}

namespace {

// The network in double, straight from its definition (dfaoit_network.h's layout).
glm::dvec3 mlpInDouble(const methods::DfaoitParameters& p, const double x[10]) {
  const float* w1 = p.data();
  const float* b1 = w1 + 320;
  const float* w2 = b1 + 32;
  const float* b2 = w2 + 512;
  const float* w3 = b2 + 16;
  const float* b3 = w3 + 48;
  double h1[32], h2[16];
  for (int i = 0; i < 32; ++i) {
    double s = b1[i];
    for (int j = 0; j < 10; ++j) s += double(w1[i * 10 + j]) * x[j];
    h1[i] = s > 0 ? s : 0;
  }
  for (int i = 0; i < 16; ++i) {
    double s = b2[i];
    for (int j = 0; j < 32; ++j) s += double(w2[i * 32 + j]) * h1[j];
    h2[i] = s > 0 ? s : 0;
  }
  glm::dvec3 y;
  for (int i = 0; i < 3; ++i) {
    double s = b3[i];
    for (int j = 0; j < 16; ++j) s += double(w3[i * 16 + j]) * h2[j];
    y[i] = 1 / (1 + std::exp(-s));
  }
  return y;
}

}  // namespace

TEST_CASE("dfaoit: exact up to two layers, the network on the paper's features beyond", "[methods][dfaoit]") {
  const FrameResult df = render(reference().scene, "dfaoit", {{"accum", "rgba32f"}});
  const methods::DfaoitParameters& p = methods::dfaoitTrainedParameters();
  int inferred = 0;
  forEachPixel([&](int x, int y, std::vector<TransparentFragment> f, glm::dvec3 c0) {
    if (f.empty()) return requireClose(df.finalFloat, x, y, c0, 0.0, "dfaoit, no layer");
    std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.windowDepth < b.windowDepth; });
    double t = 1;
    for (const auto& fr : f) t *= 1.0 - fr.color.a;
    if (f.size() <= 2) return requireClose(df.finalFloat, x, y, overBackToFront(f, c0), 8 * kU32 * 4, "dfaoit, exact path");
    ++inferred;
    // The features (paper §3.1) in double from the sorted fragments.
    const glm::dvec4 a(f[0].color), b(f[1].color);
    const glm::dvec3 g = glm::dvec3(a) * a.a + glm::dvec3(b) * ((1 - a.a) * b.a);
    glm::dvec3 rest(0.0), acc(0.0);
    double restAlpha = 0;
    for (size_t i = 0; i < f.size(); ++i) {
      acc += glm::dvec3(glm::vec3(f[i].color)) * double(f[i].color.a);
      if (i >= 2) rest += glm::dvec3(glm::vec3(f[i].color)), restAlpha += f[i].color.a;
    }
    const double m = double(f.size()) - 2;
    const double features[10] = {g.r, g.g, g.b, restAlpha / m, rest.r / m, rest.g / m, rest.b / m, acc.r, acc.g, acc.b};
    // fp32 sums and a fp32 network: its weights amplify the features' roundings by at most
    // Π‖W‖ (a few hundred here), so 1e-3 is loose for that and tight for any other formula.
    requireClose(df.finalFloat, x, y, mlpInDouble(p, features) + c0 * t, 1e-3, "dfaoit, network");
  });
  CHECK(inferred > 200);
}

TEST_CASE("meshkin3: Vallius's listing 4.1 by hand and in closed form", "[methods][meshkin3]") {
  // out = t1.rgb − bg·t1.a + bg·t3.a + bg·t2.rgb·t3.a with t1 = Σ(c·α, α), t2 = Σ(1/α, …, α),
  // t3 = Π(c, α). By hand, over a blue background:
  //   no layers:                            bg = (0, 0, 1)
  //   red at α = 0.5:                       (0.5, 0, 0) + bg·(0.5·3 − 0.5) = (0.5, 0, 1)
  //   red at 0.5 and green at 0.25:          (0.5, 0.25, 0) + bg·(0.125·7 − 0.75) = (0.5, 0.25, 0.125)
  // (OVER would give (0.5, 0, 0.5) and (0.5, 0.125, 0.375) or (0.375, 0.25, 0.375)).
  Scene s = layerScene(8, {0, 0, 1});
  requireClose(render(s, "meshkin3").finalFloat, 4, 4, {0, 0, 1}, 0, "meshkin3, no layers");
  s.objects = {quad({0, 0, 0}, 10, {1, 0, 0, 0.5f})};
  requireClose(render(s, "meshkin3").finalFloat, 4, 4, {0.5, 0, 1}, 0, "meshkin3, one layer");
  s.objects.push_back(quad({0, 0, -1}, 10, {0, 1, 0, 0.25f}));
  requireClose(render(s, "meshkin3").finalFloat, 4, 4, {0.5, 0.25, 0.125}, 0, "meshkin3, two layers");
  // The test scene in fp32 targets against the closed form Σαc + bg·(Πα·(1 + Σ1/α) − Σα). Its
  // particles fade to α = 0 at their rims: there 1/α is infinite and Πα is 0, so the closed form
  // and the method both give NaN (inf·0), as a GPU running the listing would.
  const FrameResult m = render(reference().scene, "meshkin3", {{"format", "rgba32f"}});
  int compared = 0, nan = 0;
  forEachPixel([&](int x, int y, const std::vector<TransparentFragment>& f, glm::dvec3 c0) {
    glm::dvec3 sum(0.0);
    double sumA = 0, prodA = 1, sumInv = 0;
    for (const auto& fr : f) {
      sum += glm::dvec3(glm::vec3(fr.color)) * double(fr.color.a);
      sumA += fr.color.a;
      prodA *= fr.color.a;
      sumInv += 1.0 / fr.color.a;
    }
    const glm::dvec3 want = sum + c0 * (prodA * (1 + sumInv) - sumA);
    ++compared;
    if (std::isnan(want.x)) {
      ++nan;
      CHECK(std::isnan(m.finalFloat.fetch(x, y).r));
      return;
    }
    requireClose(m.finalFloat, x, y, want, (f.size() + 3) * 8 * kU32 * (1 + sumInv), "meshkin3");
  });
  CHECK(compared == 64 * 48);
  CHECK(nan < 200);
}

TEST_CASE("dualpeel: outputs=changing leaves every attachment as the sample's shader (outputs=all) does",
          "[methods][dualpeel]") {
  // The default leaves out the writes that MAX ignores and copies the front target instead of
  // passing it through (dualpeel.cpp, PeelingPassWrites). The oracle is the sample's shader,
  // which writes every output of every fragment: every attachment must have the same bits, for
  // every colour format and profile, on scenes with ties at the front and the back, α = 0 texels,
  // colour channels of −0, and more layers than a pass can peel.
  Scene ties = layerScene(12, {0.2f, 0.3f, 0.4f});
  // The farthest layer first, so that the nearer layers' writes to the back target follow its own.
  ties.objects = {quad({0, 0, -1.5f}, 10, {0.3f, -0.0f, 0.9f, 0.75f}), quad({0, 0, 0}, 10, {1, 0, 0, 0.5f}),
                  quad({0, 0, 0}, 10, {0, 0, 1, 0.5f}), quad({0, 0, -0.5f}, 10, {-0.0f, 0.5f, -0.0f, 0.25f}),
                  quad({0, 0, -1}, 10, {0.6f, 0.2f, -0.0f, 0.5f}), quad({0, 0, -1}, 10, {0.2f, 0.4f, 0.1f, 0.5f})};
  Scene deep = layerScene(24, {0.1f, 0.1f, 0.1f});
  deep.objects.clear();
  for (int i = 0; i < 40; ++i)  // 40 overlapping layers, fewer than 64 passes can peel
    deep.objects.push_back(quad({0.02f * float(i % 5), 0.0f, -0.05f * float(i)}, 8.0f - 0.1f * float(i),
                                {0.1f * float(i % 10), 1.0f - 0.02f * float(i), 0.5f, 0.1f + 0.02f * float(i)}));
  const std::pair<const char*, const Scene*> scenes[] = {{"reference", &reference().scene}, {"ties", &ties}, {"deep", &deep}};
  Renderer renderer(RendererOptions{2, 16});
  int compared = 0;
  for (const auto& entry : scenes) {  // not a structured binding: clang 14's lambdas cannot capture one
    const char* name = entry.first;
    const Scene* scene = entry.second;
    const SceneGeometry g = buildSceneGeometry(*scene);
    for (const Profile& profile : {exactProfile(), llvmpipeProfile(), nvidiaProfile()})
      for (const char* color : {"rgba8", "rgba16f", "rgba32f"}) {
        auto frame = [&](const char* outputs) {
          return makeMethod("dualpeel", {{"color", color}, {"outputs", outputs}})
              ->render(FrameContext{*scene, g, scene->width, scene->height, profile, renderer});
        };
        const FrameResult changing = frame("changing"), all = frame("all");
        INFO(name << " " << profile.describe() << " color=" << color);
        REQUIRE(changing.dump.size() == all.dump.size());
        for (size_t i = 0; i < all.dump.size(); ++i) {
          INFO(all.dump[i].first);
          CHECK(changing.dump[i].second.sameBits(all.dump[i].second));
        }
        CHECK(changing.final8.sameBits(all.final8));
        CHECK(changing.finalFloat.sameBits(all.finalFloat));
        CHECK(changing.stats == all.stats);
        ++compared;
      }
  }
  CHECK(compared == 27);
}

TEST_CASE("every method renders finite pixels at its defaults unless it declares when it does not", "[methods]") {
  // MethodInfo::nonFiniteWhen is what `oitref methods` prints and what the options fuzzer
  // (tests/fuzz/fuzz_options.cpp) trusts: a method that leaves it empty must not give NaN or inf on
  // the test scene, whose particles fade to α = 0 at their rims; one that fills it must show it.
  for (const MethodInfo& info : allMethods()) {
    const FrameResult frame = render(reference().scene, info.name);
    int nonFinite = 0;
    for (int y = 0; y < frame.finalFloat.height(); ++y)
      for (int x = 0; x < frame.finalFloat.width(); ++x)
        for (int c = 0; c < 4; ++c) nonFinite += !std::isfinite(frame.finalFloat.fetch(x, y)[c]);
    INFO(info.name << ": " << nonFinite << " non-finite channels");
    CHECK((nonFinite > 0) == !info.nonFiniteWhen.empty());
  }
}
