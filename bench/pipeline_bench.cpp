// Pipeline throughput at 1920×1080, one thread and all threads. Numbers are printed, never
// asserted. Each case reports the median of --repeat runs (after one warm-up).
//
//   opaque_fill        8 full-screen quads at shuffled depths, depth test LESS + write, RGBA8
//   blend_rgba8        8 full-screen layers blended OVER into RGBA8
//   blend_rgba16f      the same into RGBA16F
//   accum_wboit        8 layers into RGBA16F (ONE, ONE) + R16F (ZERO, ONE_MINUS_SRC_COLOR) with a
//                      McGuire–Bavoil eq. 7 weight computed in the shader
//   small_triangles    1M triangles of about 2 pixels: setup + binning and rasterization
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "oitref/core/renderer.h"

using namespace oitref;

namespace {

constexpr int kW = 1920, kH = 1080;

glm::vec4 clipOf(double x, double y, double z) {
  return {float(x / (kW * 0.5) - 1.0), float(y / (kH * 0.5) - 1.0), float(2 * z - 1), 1.0f};
}

Geometry layers(int n, int attributes) {
  Geometry g;
  g.attributeCount = attributes;
  const int order[8] = {3, 7, 1, 5, 0, 6, 2, 4};
  for (int i = 0; i < n; ++i) {
    const double z = 0.1 + 0.1 * order[i % 8];
    const glm::dvec2 p[6] = {{0, 0}, {kW, 0}, {kW, kH}, {0, 0}, {kW, kH}, {0, kH}};
    for (const auto& q : p) {
      g.clipPositions.push_back(clipOf(q.x, q.y, z));
      for (int a = 0; a < attributes; ++a) g.attributes.push_back(0.1f + 0.1f * float((i + a) % 8));
    }
  }
  return g;
}

Geometry smallTriangles(size_t n) {
  Geometry g;
  std::mt19937 rng(1);
  auto u = [&](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 8) / 16777216.0; };
  for (size_t i = 0; i < n; ++i) {
    const double x = u(0, kW), y = u(0, kH), z = u(0.1, 0.9);
    g.clipPositions.push_back(clipOf(x, y, z));
    g.clipPositions.push_back(clipOf(x + 2, y, z));
    g.clipPositions.push_back(clipOf(x, y + 2, z));
  }
  return g;
}

struct Result {
  double ms, setupMs;
  uint64_t fragments, triangles;
};

Result measure(int repeat, const std::function<DrawStats()>& run) {
  run();  // warm-up
  std::vector<double> ms, setup;
  DrawStats last;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    last = run();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    setup.push_back(last.setupMs);
  }
  std::sort(ms.begin(), ms.end());
  std::sort(setup.begin(), setup.end());
  return {ms[ms.size() / 2], setup[setup.size() / 2], last.fragmentsRasterized, last.trianglesSubmitted};
}

std::string onlyCase;  // --case NAME: run just that one
bool wanted(const char* name) { return onlyCase.empty() || onlyCase == name; }

void print(const char* name, int threads, const Result& r) {
  const double fps = double(r.fragments) / (r.ms * 1e-3);
  std::printf("%-16s %7d %10.2f %12llu %12.1f %10.2f %12.1f\n", name, threads, r.ms, (unsigned long long)r.fragments,
              fps / 1e6, r.ms * 1e6 / double(r.fragments), fps / 1e6 / threads);
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 5;
  std::vector<int> threadCounts = {1, int(std::max(1u, std::thread::hardware_concurrency()))};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threadCounts = {std::max(1, std::atoi(argv[++i]))};
    else if (!std::strcmp(argv[i], "--case") && i + 1 < argc) onlyCase = argv[++i];
    else {
      std::fprintf(stderr, "usage: oitref_bench [--repeat N] [--threads N] [--case NAME]\n");
      return 2;
    }
  }
  if (threadCounts.size() == 2 && threadCounts[0] == threadCounts[1]) threadCounts.pop_back();

  const Geometry eight = layers(8, 4);
  const Geometry tiny = smallTriangles(1'000'000);
  std::printf("oitref pipeline benchmark, %dx%d, median of %d runs\n", kW, kH, repeat);
  std::printf("%-16s %7s %10s %12s %12s %10s %12s\n", "case", "threads", "ms", "fragments", "Mfrag/s", "ns/frag",
              "Mfrag/s/thr");
  for (int threads : threadCounts) {
    Renderer r(RendererOptions{threads, 64});
    Image rgba8(makeFormat(FormatId::RGBA8), kW, kH), rgba16f(makeFormat(FormatId::RGBA16F), kW, kH);
    Image reveal(makeFormat(FormatId::R16F), kW, kH);
    DepthBuffer depth(DepthFormat::D24, kW, kH);
    const Profile exact = exactProfile();
    // Batch programs (programOf), as the methods draw.
    const FragmentProgram color = programOf([](const FragmentInput& in, FragmentOutput& o) { o.write(0, in.vec4At(0)); });

    if (wanted("opaque_fill")) {
      Framebuffer fb;
      fb.color[0] = &rgba8;
      fb.depth = &depth;
      PipelineState st;
      st.depth = {true, CompareFunc::Less, true, false};
      print("opaque_fill", threads, measure(repeat, [&] {
              depth.clear(1.0);
              return r.draw(fb, st, eight, color);
            }));
    }
    for (Image* target : {&rgba8, &rgba16f}) {
      if (!wanted(target == &rgba8 ? "blend_rgba8" : "blend_rgba16f")) continue;
      Framebuffer fb;
      fb.color[0] = target;
      PipelineState st;
      st.blend[0] = BlendState::separate(BlendEquation::Add, BlendEquation::Add, BlendFactor::SrcAlpha,
                                         BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::OneMinusSrcAlpha);
      print(target == &rgba8 ? "blend_rgba8" : "blend_rgba16f", threads, measure(repeat, [&] {
              target->clear(glm::vec4(0), exact);
              return r.draw(fb, st, eight, color);
            }));
    }
    if (wanted("accum_wboit")) {
      Framebuffer fb;
      fb.color[0] = &rgba16f;
      fb.color[1] = &reveal;
      PipelineState st;
      st.blend[0] = BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::One);
      st.blend[1] = BlendState::same(BlendEquation::Add, BlendFactor::Zero, BlendFactor::OneMinusSrcColor);
      const FragmentProgram accumulate = programOf([](const FragmentInput& in, FragmentOutput& o) {
        const glm::vec4 c = in.vec4At(0);
        const float z = in.viewDepth * 50.0f;
        const float a = z / 5, b = z / 200, b3 = b * b * b;
        const float w = c.a * std::clamp(10.0f / (1e-5f + a * a + b3 * b3), 1e-2f, 3e3f);
        o.write(0, glm::vec4(glm::vec3(c) * c.a, c.a) * w);
        o.write(1, glm::vec4(c.a));
      });
      print("accum_wboit", threads, measure(repeat, [&] {
              rgba16f.clear(glm::vec4(0), exact);
              reveal.clear(glm::vec4(1), exact);
              return r.draw(fb, st, eight, accumulate);
            }));
    }
    if (wanted("composite_wboit")) {
      // WBOIT's composite (methods' compositeWeighted): a full-screen pass that fetches the
      // accumulation (rgba32f) and revealage (r32f) of its pixel and blends the resolved colour
      // over the RGBA8 background and the RGBA32F analysis copy, in the `llvmpipe` profile.
      Image accum(makeFormat(FormatId::RGBA32F), kW, kH), revealage(makeFormat(FormatId::R32F), kW, kH);
      Image analysis(makeFormat(FormatId::RGBA32F), kW, kH);
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const float a = float((x * 7 + y * 13) % 97) / 16.0f;
          accum.store(x, y, glm::vec4(a * 0.3f, a * 0.5f, a * 0.2f, a), exact);
          revealage.store(x, y, glm::vec4(float((x + y) % 101) / 100.0f), exact);
        }
      Framebuffer fb;
      fb.color[0] = &rgba8;
      fb.color[1] = &analysis;
      PipelineState st;
      st.profile = llvmpipeProfile();
      st.blend[0] = st.blend[1] = BlendState::separate(BlendEquation::Add, BlendEquation::Add, BlendFactor::OneMinusSrcAlpha,
                                                        BlendFactor::SrcAlpha, BlendFactor::Zero, BlendFactor::One);
      const FragmentProgram composite = programOf([&](const FragmentInput& in, FragmentOutput& o) {
        const glm::vec4 a = accum.fetch(in.x, in.y);
        const glm::vec4 s(glm::vec3(a) / std::clamp(a.a, 1e-4f, 5e4f), revealage.fetch(in.x, in.y).r);
        o.write(0, s);
        o.write(1, s);
      });
      // Cleared once: each run blends over the last one's result, the same work (the clears of
      // 41 MB would be a third of the time).
      rgba8.clear(glm::vec4(0.25f, 0.5f, 0.75f, 1.0f), exact);
      analysis.clear(glm::vec4(0.25f, 0.5f, 0.75f, 1.0f), exact);
      print("composite_wboit", threads, measure(repeat, [&] { return r.drawFullscreen(fb, st, composite); }));
    }
    if (wanted("small_triangles")) {
      Framebuffer fb;
      fb.color[0] = &rgba8;
      PipelineState st;
      const FragmentProgram white = programOf([](const FragmentInput&, FragmentOutput& o) { o.write(0, glm::vec4(1)); });
      const Result res = measure(repeat, [&] { return r.draw(fb, st, tiny, white); });
      print("small_triangles", threads, res);
      std::printf("%-16s %7d %10.2f ms setup+binning for %llu triangles: %.1f M triangles/s\n", "  setup+binning",
                  threads, res.setupMs, (unsigned long long)res.triangles, double(res.triangles) / (res.setupMs * 1e-3) / 1e6);
    }
  }
  return 0;
}
