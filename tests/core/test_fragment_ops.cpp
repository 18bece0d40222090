// Per-fragment operations: primitive order, early/late depth, discard, depth writes, MRT,
// write masks, full-screen passes, texel fetch between passes, viewport.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <utility>

#include "oitref/core/blend.h"
#include "render_helpers.h"
#include "support.h"

using namespace oitref;

namespace {

constexpr int W = 24, H = 20;

glm::vec4 colorOf(uint32_t id) {
  return {float((id * 37) % 101) / 100.0f, float((id * 53) % 97) / 96.0f, float((id * 17) % 89) / 88.0f,
          0.05f + float(id % 9) / 10.0f};
}

Geometry overlappingTriangles(int n, uint32_t seed) {
  test::BitStream rng(seed);
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < n; ++i) {
    const double z = rng.uniform(0.1f, 0.9f);
    for (int k = 0; k < 3; ++k) pts.emplace_back(rng.uniform(-10, W + 10), rng.uniform(-10, H + 10), z);
  }
  return test::windowTriangles(pts, W, H);
}

// A colour attachment's bytes followed by a depth buffer's stored words: what two renders that
// must agree are compared by.
std::vector<uint8_t> attachmentBytes(const Image& color, const DepthBuffer& depth) {
  std::vector<uint8_t> bytes(color.bytes().begin(), color.bytes().end());
  for (int y = 0; y < depth.height(); ++y)
    for (int x = 0; x < depth.width(); ++x) {
      const uint32_t d = depth.load(x, y);
      bytes.insert(bytes.end(), reinterpret_cast<const uint8_t*>(&d), reinterpret_cast<const uint8_t*>(&d) + 4);
    }
  return bytes;
}

// `triangles` perspective triangles of a kSheetsW × kSheetsH framebuffer in four sheets of
// nearly equal depth, each slightly tilted: their depth codes tie or differ by a step in d16 and
// d24, so depth-tested runs pass, fail and straddle.
constexpr int kSheetsW = 160, kSheetsH = 120;
Geometry nearlyEqualSheets(test::BitStream& rng, int triangles) {
  constexpr int kW = kSheetsW, kH = kSheetsH;
  Geometry g;
  for (int i = 0; i < triangles; ++i) {
    const double sheet = 0.2 + 0.15 * double(rng.next() % 4), tilt = rng.uniform(-0.05f, 0.05f);
    for (int k = 0; k < 3; ++k) {
      const double x = rng.uniform(-20, kW + 20), y = rng.uniform(-20, kH + 20), w = rng.uniform(1.0f, 8.0f);
      const double zn = sheet + tilt * x / kW + rng.uniform(-1e-7f, 1e-7f);
      g.clipPositions.push_back(glm::vec4(float((2 * x / kW - 1) * w), float((2 * y / kH - 1) * w), float(zn * w), float(w)));
    }
  }
  return g;
}

const BlendState kOver = BlendState::separate(BlendEquation::Add, BlendEquation::Add, BlendFactor::SrcAlpha,
                                              BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::OneMinusSrcAlpha);

}  // namespace

TEST_CASE("fragment ops: each pixel blends its fragments in primitive submission order", "[fragment]") {
  // OVER does not commute: the result is right only if the order is. The expectation is built by
  // calling the blend function on each pixel in submission order, using the recorded coverage.
  const int n = 120;
  const Geometry g = overlappingTriangles(n, 5);
  Renderer r(RendererOptions{3, 8});
  for (const char* fmt : {"rgba16f", "rgba8", "r11g11b10f"}) {
    const Format f = parseFormat(fmt);
    Image img(f, W, H);
    img.clear({0.2f, 0.3f, 0.4f, 1}, exactProfile());
    Framebuffer fb;
    fb.color[0] = &img;
    PipelineState st;
    st.blend[0] = kOver;
    r.draw(fb, st, g, {[](const FragmentInput& in, FragmentOutput& o) { o.write(0, colorOf(in.primitiveId)); }});
    // Coverage of each triangle alone.
    std::vector<std::vector<float>> cover;
    for (int t = 0; t < n; ++t) {
      Geometry one;
      one.clipPositions.assign(g.clipPositions.begin() + 3 * t, g.clipPositions.begin() + 3 * t + 3);
      cover.push_back(test::coverageCount(r, one, W, H));
    }
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        uint8_t want[16];
        encodeTexel(f, {0.2f, 0.3f, 0.4f, 1}, exactProfile(), want);
        for (int t = 0; t < n; ++t)
          if (cover[size_t(t)][size_t(y * W + x)] == 1.0f)
            blendIntoTexel(f, kOver, glm::vec4(0), exactProfile(), colorOf(uint32_t(t)), want);
        REQUIRE(std::memcmp(want, img.texel(x, y), f.bytesPerTexel()) == 0);
      }
  }
}

TEST_CASE("fragment ops: depth test order, early and late tests, discard and depth writes", "[fragment]") {
  Renderer r(RendererOptions{2, 8});
  // Two full-screen triangles pairs: near (z .25) drawn after far (z .75).
  const auto quad = [](double z) {
    return std::vector<glm::dvec3>{{-1, -1, z}, {W + 1, -1, z}, {W + 1, H + 1, z},
                                   {-1, -1, z}, {W + 1, H + 1, z}, {-1, H + 1, z}};
  };
  std::vector<glm::dvec3> both = quad(0.75);
  for (const auto& p : quad(0.25)) both.push_back(p);
  const Geometry g = test::windowTriangles(both, W, H);

  auto render = [&](FragmentProgram prog, DepthState ds, DepthFormat df = DepthFormat::D24) {
    Image img(makeFormat(FormatId::R32F), W, H);
    img.clear(glm::vec4(-1), exactProfile());
    DepthBuffer depth(df, W, H);
    Framebuffer fb;
    fb.color[0] = &img;
    fb.depth = &depth;
    PipelineState st;
    st.depth = ds;
    const DrawStats s = r.draw(fb, st, g, prog);
    return std::make_tuple(img.fetch(3, 3).r, depth.depth(3, 3), s);
  };
  const DepthState less{true, CompareFunc::Less, true, false};
  const auto writeId = [](const FragmentInput& in, FragmentOutput& o) { o.write(0, glm::vec4(float(in.primitiveId))); };

  // Plain: the near pair (primitives 2, 3) wins; the depth buffer holds 0.25.
  auto [c1, d1, s1] = render({writeId}, less);
  CHECK(c1 >= 2.0f);
  CHECK(d1 == Approx(0.25).margin(1e-7));
  CHECK(s1.fragmentsShaded == s1.fragmentsRasterized);  // nothing fails: near comes second

  // GREATER with the far pair first: the near pair fails; early tests skip its shading.
  auto [c2, d2, s2] = render({writeId}, {true, CompareFunc::Greater, true, false});
  CHECK(c2 == -1.0f);  // cleared depth is 1.0: nothing is greater
  CHECK(s2.fragmentsShaded == 0);
  CHECK(s2.fragmentsDepthFailed == s2.fragmentsRasterized);

  // Depth test disabled: no depth writes even with the write mask on (GL §17.3.4).
  auto [c3, d3, s3] = render({writeId}, {false, CompareFunc::Less, true, false});
  CHECK(d3 == 1.0);

  // A shader that discards the near pair: late test, the far pair's depth stays.
  const FragmentProgram discardNear{[](const FragmentInput& in, FragmentOutput& o) {
                                      if (in.primitiveId >= 2) o.discard();
                                      else o.write(0, glm::vec4(float(in.primitiveId)));
                                    },
                                    true, false, false};
  auto [c4, d4, s4] = render(discardNear, less);
  CHECK(c4 < 2.0f);
  CHECK(d4 == Approx(0.75).margin(1e-7));
  CHECK(s4.fragmentsDiscarded > 0);
  // Forced early fragment tests: the depth write happens before the discard.
  FragmentProgram early = discardNear;
  early.earlyFragmentTests = true;
  auto [c5, d5, s5] = render(early, less);
  CHECK(c5 < 2.0f);
  CHECK(d5 == Approx(0.25).margin(1e-7));

  // gl_FragDepth: the far pair writes depth 0.1, so the near pair (0.25) fails LESS.
  const FragmentProgram writesDepth{[](const FragmentInput& in, FragmentOutput& o) {
                                      if (in.primitiveId < 2) o.setDepth(0.1f);
                                      o.write(0, glm::vec4(float(in.primitiveId)));
                                    },
                                    false, true, false};
  auto [c6, d6, s6] = render(writesDepth, less, DepthFormat::D32F);
  CHECK(c6 < 2.0f);
  CHECK(d6 == double(0.1f));
}

TEST_CASE("fragment ops: eight targets of different formats, each with its own blend state", "[fragment]") {
  Renderer r(RendererOptions{2, 8});
  const char* formats[8] = {"rgba8", "rgba16f", "r32f", "rgb10a2", "r11g11b10f", "rg16f", "rgba:e8m7", "r8"};
  std::vector<Image> images;
  for (const char* f : formats) images.emplace_back(parseFormat(f), W, H);
  Framebuffer fb;
  PipelineState st;
  for (int i = 0; i < 8; ++i) {
    images[size_t(i)].clear(glm::vec4(0.5f), exactProfile());
    fb.color[size_t(i)] = &images[size_t(i)];
    st.blend[size_t(i)] = i % 2 ? BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::One) : BlendState{};
  }
  const Geometry g = test::windowTriangles({{-1, -1, .5}, {60, -1, .5}, {-1, 60, .5}}, W, H);
  r.draw(fb, st, g, {[](const FragmentInput&, FragmentOutput& o) {
           for (int t = 0; t < 8; ++t)
             if (t != 5) o.write(t, glm::vec4(0.125f * float(t + 1)));  // target 5 not written
         }});
  for (int t = 0; t < 8; ++t) {
    const Format f = images[size_t(t)].format();
    const glm::vec4 src(0.125f * float(t + 1));
    uint8_t want[16];
    encodeTexel(f, glm::vec4(0.5f), exactProfile(), want);
    if (t != 5) blendIntoTexel(f, st.blend[size_t(t)], glm::vec4(0), exactProfile(), src, want);
    INFO("target " << t << " " << f.name());
    CHECK(std::memcmp(want, images[size_t(t)].texel(2, 2), f.bytesPerTexel()) == 0);
  }
}

TEST_CASE("fragment ops: full-screen passes, texel fetch of an earlier pass, viewport", "[fragment]") {
  Renderer r(RendererOptions{2, 8});
  Image first(makeFormat(FormatId::RGBA16F), W, H), second(makeFormat(FormatId::RGBA32F), W, H);
  first.clear(glm::vec4(0), exactProfile());
  second.clear(glm::vec4(0), exactProfile());
  Framebuffer fb1;
  fb1.color[0] = &first;
  PipelineState st;
  DrawStats s = r.drawFullscreen(fb1, st, {[](const FragmentInput& in, FragmentOutput& o) {
                                   o.write(0, {in.fragCoord.x, in.fragCoord.y, float(in.x * 100 + in.y), 1});
                                 }});
  CHECK(s.fragmentsShaded == uint64_t(W * H));
  Framebuffer fb2;
  fb2.color[0] = &second;
  st.viewport = {4, 3, 10, 8};
  r.drawFullscreen(fb2, st, {[&](const FragmentInput& in, FragmentOutput& o) {
                     o.write(0, first.fetch(in.x, in.y) * 2.0f);
                   }});
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const glm::vec4 v = second.fetch(x, y);
      const bool inside = x >= 4 && x < 14 && y >= 3 && y < 11;
      INFO("pixel " << x << "," << y);
      if (inside) {
        CHECK(v.x == 2 * (x + 0.5f));
        CHECK(v.y == 2 * (y + 0.5f));
        CHECK(v.z == 2 * float(x * 100 + y));
      } else {
        CHECK(v.x == 0.0f);
      }
    }
}

TEST_CASE("fragment ops: a batch program gives the per-fragment program's attachments and counts", "[fragment]") {
  // The per-fragment shader is the oracle of FragmentProgram::batch (programOf): the same draws,
  // once with the shader alone and once with the batch, must leave identical bytes in the colour
  // and depth attachments and identical counts — with early and late tests, discard, gl_FragDepth
  // and a full-screen pass that reads an earlier pass's attachment.
  const Geometry g = overlappingTriangles(150, 11);
  const auto shader = [](const FragmentInput& in, FragmentOutput& o) {
    if (in.primitiveId % 5 == 1 && in.x % 3 == 0) return o.discard();
    if (in.primitiveId % 4 == 2) o.setDepth(float(in.x) / float(W) * 0.5f + 0.1f);
    o.write(0, colorOf(in.primitiveId) * (0.5f + in.depth));
    if (in.primitiveId % 2) o.write(1, glm::vec4(in.fragCoord, in.viewDepth, in.frontFacing ? 1.0f : 0.0f));
  };
  for (bool early : {false, true}) {
    std::vector<uint8_t> bytes[2];
    DrawStats stats[2];
    for (int batch = 0; batch < 2; ++batch) {
      Renderer r(RendererOptions{2, 8});
      Image a(makeFormat(FormatId::RGBA16F), W, H), b(makeFormat(FormatId::RGBA8), W, H), c(makeFormat(FormatId::RGBA32F), W, H);
      a.clear({0.1f, 0.2f, 0.3f, 1}, exactProfile());
      b.clear({0.4f, 0.5f, 0.6f, 1}, exactProfile());
      DepthBuffer depth(DepthFormat::D24, W, H);
      Framebuffer fb;
      fb.color[0] = &a, fb.color[1] = &b, fb.depth = &depth;
      PipelineState st;
      st.blend[0] = kOver;
      st.depth = {true, CompareFunc::Less, true, false};
      FragmentProgram program = batch ? programOf(shader, true, true, early) : FragmentProgram{shader, true, true, early};
      stats[batch] = r.draw(fb, st, g, program);
      // A full-screen pass that fetches the first pass's target.
      Framebuffer full;
      full.color[0] = &c;
      const auto fetch = [&a](const FragmentInput& in, FragmentOutput& o) {
        if ((in.x + in.y) % 7) o.write(0, a.fetch(in.x, in.y) * 2.0f);
      };
      const DrawStats fs = r.drawFullscreen(full, PipelineState{}, batch ? programOf(fetch) : FragmentProgram{fetch});
      stats[batch].fragmentsWritten += fs.fragmentsWritten;
      for (const Image* image : {&a, &b}) bytes[batch].insert(bytes[batch].end(), image->bytes().begin(), image->bytes().end());
      const std::vector<uint8_t> rest = attachmentBytes(c, depth);
      bytes[batch].insert(bytes[batch].end(), rest.begin(), rest.end());
    }
    INFO("early fragment tests " << early);
    CHECK(bytes[0] == bytes[1]);
    CHECK(stats[0].fragmentsShaded == stats[1].fragmentsShaded);
    CHECK(stats[0].fragmentsDepthFailed == stats[1].fragmentsDepthFailed);
    CHECK(stats[0].fragmentsDiscarded == stats[1].fragmentsDiscarded);
    CHECK(stats[0].fragmentsWritten == stats[1].fragmentsWritten);
    CHECK(stats[1].fragmentsDiscarded > 0);
    CHECK(stats[1].fragmentsDepthFailed > 0);
  }
}

TEST_CASE("fragment ops: with no colour target bound, a batch program counts as the per-fragment one", "[fragment]") {
  // The A-buffer's passes bind only a depth buffer and store through their shaders: their batches
  // blend nothing, and the stage only counts what they discarded.
  const Geometry g = overlappingTriangles(150, 12);
  std::atomic<uint64_t> stored[2] = {0, 0};
  for (bool early : {false, true}) {
    DrawStats stats[2];
    for (int batch = 0; batch < 2; ++batch) {
      const auto shader = [&, batch](const FragmentInput& in, FragmentOutput& o) {
        if (in.primitiveId % 5 == 1 && in.x % 3 == 0) return o.discard();
        stored[batch].fetch_add(1, std::memory_order_relaxed);
        o.write(0, colorOf(in.primitiveId));  // no target bound: nothing lands
      };
      Renderer r(RendererOptions{2, 8});
      DepthBuffer depth(DepthFormat::D24, W, H);
      depth.clear(0.6);
      Framebuffer fb;
      fb.depth = &depth;
      PipelineState st;
      st.depth = {true, CompareFunc::Less, false, false};
      const FragmentProgram program = batch ? programOf(shader, true, false, early) : FragmentProgram{shader, true, false, early};
      stats[batch] = r.draw(fb, st, g, program);
    }
    INFO("early fragment tests " << early);
    CHECK(stats[0].fragmentsShaded == stats[1].fragmentsShaded);
    CHECK(stats[0].fragmentsDepthFailed == stats[1].fragmentsDepthFailed);
    CHECK(stats[0].fragmentsDiscarded == stats[1].fragmentsDiscarded);
    CHECK(stats[1].fragmentsWritten == 0);
    CHECK(stats[1].fragmentsDiscarded > 0);
    CHECK(stats[1].fragmentsDepthFailed > 0);
  }
  CHECK(stored[0] == stored[1]);
}

TEST_CASE("fragment ops: a pure program that may discard gives the late test's attachments, shading fewer", "[fragment]") {
  // FragmentProgram::pure lets fragments that fail the depth test go unshaded although the test
  // of a discarding shader comes after it. The oracle is the same program without `pure` (the
  // late test of GL §15.2.4 as written): identical colour and depth bytes for every compare
  // function and write mask, with discards, on the span and the per-fragment paths; what
  // changes is only that fewer fragments are shaded.
  const Geometry g = overlappingTriangles(160, 23);
  const auto shader = [](const FragmentInput& in, FragmentOutput& o) {
    if ((in.primitiveId + uint32_t(in.x)) % 3 == 0) return o.discard();
    o.write(0, colorOf(in.primitiveId) * (0.5f + in.depth));
  };
  int compared = 0, fewer = 0;
  for (CompareFunc func : {CompareFunc::Less, CompareFunc::LEqual, CompareFunc::Greater, CompareFunc::NotEqual})
    for (bool writeDepth : {true, false})
      for (bool perFragment : {false, true}) {
        std::vector<uint8_t> bytes[2];
        DrawStats stats[2];
        for (int pure = 0; pure < 2; ++pure) {
          Renderer r(RendererOptions{2, 8, perFragment});
          Image a(makeFormat(FormatId::RGBA8), W, H);
          a.clear({0.1f, 0.2f, 0.3f, 1}, exactProfile());
          DepthBuffer depth(DepthFormat::D24, W, H);
          depth.clear(func == CompareFunc::Greater ? 0.0 : 0.6);
          Framebuffer fb;
          fb.color[0] = &a, fb.depth = &depth;
          PipelineState st;
          st.blend[0] = kOver;
          st.depth = {true, func, writeDepth, false};
          stats[pure] = r.draw(fb, st, g, programOf(shader, true, false, false, pure == 1));
          bytes[pure] = attachmentBytes(a, depth);
        }
        INFO(toString(func) << " depth writes " << writeDepth << " per fragment " << perFragment);
        CHECK(bytes[0] == bytes[1]);
        CHECK(stats[0].fragmentsWritten == stats[1].fragmentsWritten);
        CHECK(stats[1].fragmentsShaded <= stats[0].fragmentsShaded);
        CHECK(stats[0].fragmentsWritten > 0);
        fewer += stats[1].fragmentsShaded < stats[0].fragmentsShaded;
        ++compared;
      }
  CHECK(compared == 16);
  CHECK(fewer >= 8);  // LESS and LEQUAL reject early, with or without depth writes, on both paths
}

TEST_CASE("fragment ops: spans rejected by their depth bound give the per-fragment path's bits", "[fragment]") {
  // The span path skips runs whose window-z interval (pipeline/depth_bounds.h) fails the depth
  // test at every pixel; the per-fragment path tests each fragment. Perspective triangles in a few
  // sheets of nearly equal depth (their codes tie or differ by a step in d16 and d24), drawn with
  // depth writes, so later sheets are partly hidden by earlier ones: for every depth format and
  // compare function, early tests and a pure program that discards (tested early without writing),
  // the colour and depth bytes and the counts must be the same on both paths.
  constexpr int kW = kSheetsW, kH = kSheetsH;
  test::BitStream rng(5);
  const Geometry g = nearlyEqualSheets(rng, 120);
  const auto shade = [](const FragmentInput& in, FragmentOutput& o) { o.write(0, colorOf(in.primitiveId)); };
  const auto discarding = [](const FragmentInput& in, FragmentOutput& o) {
    if ((in.primitiveId + uint32_t(in.x)) % 5 == 0) return o.discard();
    o.write(0, colorOf(in.primitiveId));
  };
  int compared = 0;
  uint64_t failed = 0;
  // Tiles of 256 give spans of several runs (kRejectRun), tiles of 16 spans shorter than one.
  for (int tile : {16, 256})
    for (DepthFormat format : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F})
      for (CompareFunc func : {CompareFunc::Less, CompareFunc::LEqual, CompareFunc::Greater, CompareFunc::GEqual,
                               CompareFunc::Equal})
        for (bool pure : {false, true}) {
          std::vector<uint8_t> bytes[2];
          DrawStats stats[2];
          for (int perFragment = 0; perFragment < 2; ++perFragment) {
            Renderer r(RendererOptions{2, tile, perFragment == 1});
            Image a(makeFormat(FormatId::RGBA8), kW, kH);
            a.clear({0.1f, 0.2f, 0.3f, 1}, exactProfile());
            DepthBuffer depth(format, kW, kH);
            const bool farther = func == CompareFunc::Greater || func == CompareFunc::GEqual;
            depth.clear(farther ? 0.0 : func == CompareFunc::Equal ? 0.5 : 1.0);
            Framebuffer fb;
            fb.color[0] = &a, fb.depth = &depth;
            PipelineState st;
            st.depth = {true, func, true, false};
            stats[perFragment] = r.draw(fb, st, g, pure ? programOf(discarding, true, false, false, true) : programOf(shade));
            bytes[perFragment] = attachmentBytes(a, depth);
          }
          INFO("tile " << tile << " " << toString(format) << " " << toString(func) << " pure " << pure);
          CHECK(bytes[0] == bytes[1]);
          CHECK(stats[0].fragmentsShaded == stats[1].fragmentsShaded);
          CHECK(stats[0].fragmentsDepthFailed == stats[1].fragmentsDepthFailed);
          CHECK(stats[0].fragmentsWritten == stats[1].fragmentsWritten);
          failed += stats[0].fragmentsDepthFailed;
          ++compared;
        }
  CHECK(compared == 60);
  CHECK(failed > 200000);  // most of the later sheets' fragments are hidden
}

TEST_CASE("fragment ops: a position-only program sees the fragments of the per-fragment path, uninterpolated where runs surely pass", "[fragment]") {
  // FragmentProgram::readsDepth false lets span() hand runs that provably pass the depth test to
  // the shader without interpolating them (FragmentStage::positionSpan). The oracle is the
  // per-fragment path, which tests every fragment's exact z: a shader that records each pixel's
  // fragments (their count and a hash of their primitive ids in arrival order) must record the
  // same on both paths, with the same counters, for every depth format and bounded compare
  // function, and with no depth test. The stored depths are sheets of nearly equal depth drawn
  // first with writes (codes that tie or differ by a step), so runs pass, fail and straddle.
  constexpr int kW = kSheetsW, kH = kSheetsH;
  test::BitStream rng(17);
  const Geometry opaque = nearlyEqualSheets(rng, 80), transparent = nearlyEqualSheets(rng, 80);
  int compared = 0, sawNaN = 0;
  uint64_t passed = 0, failed = 0;
  for (int tile : {16, 256})
    for (DepthFormat format : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F})
      for (CompareFunc func : {CompareFunc::Less, CompareFunc::LEqual, CompareFunc::Greater, CompareFunc::GEqual,
                               CompareFunc::Always, CompareFunc::Equal})
        for (bool depthTest : {true, false}) {
          if (!depthTest && func != CompareFunc::Less) continue;
          std::vector<uint64_t> seen[2];
          DrawStats stats[2];
          for (int perFragment = 0; perFragment < 2; ++perFragment) {
            Renderer r(RendererOptions{2, tile, perFragment == 1});
            DepthBuffer depth(format, kW, kH);
            const bool farther = func == CompareFunc::Greater || func == CompareFunc::GEqual;
            depth.clear(farther ? 0.0 : 1.0);
            Framebuffer fb;
            fb.depth = &depth;
            PipelineState st;
            st.depth = {true, farther ? CompareFunc::Greater : CompareFunc::Less, true, false};
            r.draw(fb, st, opaque, programOf([](const FragmentInput&, FragmentOutput&) {}));
            st.depth = {depthTest, func, false, false};
            std::vector<uint64_t>& record = seen[perFragment];
            record.assign(size_t(2 * kW * kH), 0);
            std::atomic<int> nan{0};
            FragmentProgram program = programOfBatch([&record, &nan](const FragmentBatch& in, FragmentBatchOutput&) {
              for (int i = 0; i < in.count; ++i) {
                const size_t p = size_t(in.y) * kW + size_t(in.x[i]);
                ++record[2 * p];
                record[2 * p + 1] = record[2 * p + 1] * 1000003u + in.primitiveId + 1;
                if (std::isnan(in.depth[i])) nan.fetch_add(1, std::memory_order_relaxed);
              }
            });
            program.attributesRead = 0;
            program.readsDepth = false;
            stats[perFragment] = r.draw(fb, st, transparent, program);
            sawNaN += nan.load();
          }
          INFO("tile " << tile << " " << toString(format) << " " << toString(func) << " depth test " << depthTest);
          CHECK(seen[0] == seen[1]);
          CHECK(stats[0].fragmentsRasterized == stats[1].fragmentsRasterized);
          CHECK(stats[0].fragmentsShaded == stats[1].fragmentsShaded);
          CHECK(stats[0].fragmentsDepthFailed == stats[1].fragmentsDepthFailed);
          passed += stats[0].fragmentsShaded;
          failed += stats[0].fragmentsDepthFailed;
          ++compared;
        }
  CHECK(compared == 42);
  CHECK(passed > 200000);
  CHECK(failed > 200000);
  CHECK(sawNaN > 100000);  // the span path did skip interpolating runs that surely pass
}

TEST_CASE("fragment ops: runs decided by their tile row's stored depth range give the per-fragment path's bits", "[fragment]") {
  // A draw that tests depth without writing it summarises each tile row's stored depths once
  // (least and greatest: FragmentStage::rowDepthRange) and decides a run against that range
  // before reading its own depths: all pass (no per-fragment test) or all fail (skipped). The
  // oracle is the per-fragment path. Stored depths: sheets of nearly equal depth drawn with
  // writes (codes that tie or differ by a step), plus pokes of values the range cannot order
  // (D32F −0, NaN, −0.5, 2) and of the extreme codes, so that runs pass, fail, straddle and
  // meet unordered rows. Additive blending into fp32, so a fragment lost, added or reordered
  // changes the bytes. A program that reads no depth (FragmentProgram::readsDepth false) gets
  // NaN depths in the runs that surely pass, and the same bytes.
  constexpr int kW = kSheetsW, kH = kSheetsH;
  test::BitStream rng(23);
  const Geometry opaque = nearlyEqualSheets(rng, 80);
  Geometry transparent = nearlyEqualSheets(rng, 80);  // with an attribute, so that the barycentrics count
  transparent.attributeCount = 1;
  for (size_t v = 0; v < transparent.vertexCount(); ++v) transparent.attributes.push_back(rng.uniform(-3.0f, 3.0f));
  std::atomic<uint64_t> nanDepths{0};
  const auto shade = [&nanDepths](const FragmentInput& in, FragmentOutput& o) {
    if (std::isnan(in.depth)) nanDepths.fetch_add(1, std::memory_order_relaxed);
    const glm::vec4 c = colorOf(in.primitiveId);
    o.write(0, {c.r, c.g, c.b, in.attributes[0]});
  };
  int compared = 0;
  uint64_t passed = 0, failed = 0;
  for (int tile : {16, 256})
    for (DepthFormat format : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F})
      for (CompareFunc func : {CompareFunc::Less, CompareFunc::LEqual, CompareFunc::Greater, CompareFunc::GEqual,
                               CompareFunc::Always})
        for (bool poked : {false, true})
        for (bool readsDepth : {true, false}) {
          std::vector<uint8_t> bytes[2];
          DrawStats stats[2];
          for (int perFragment = 0; perFragment < 2; ++perFragment) {
            Renderer r(RendererOptions{2, tile, perFragment == 1});
            Image sum(makeFormat(FormatId::RGBA32F), kW, kH);
            sum.clear({0, 0, 0, 0}, exactProfile());
            DepthBuffer depth(format, kW, kH);
            const bool farther = func == CompareFunc::Greater || func == CompareFunc::GEqual;
            depth.clear(farther ? 0.0 : 1.0);
            Framebuffer fb;
            fb.color[0] = &sum, fb.depth = &depth;
            PipelineState st;
            st.depth = {true, farther ? CompareFunc::Greater : CompareFunc::Less, true, false};
            r.draw(fb, st, opaque, programOf([](const FragmentInput&, FragmentOutput&) {}));
            if (poked) {
              test::BitStream pokes(7);  // the same pixels and values on both paths
              const uint32_t d32[] = {0x80000000u, 0x7fc00000u, 0xbf000000u, 0x40000000u, 0u, 0x3f800000u};
              const uint32_t top = format == DepthFormat::D16 ? 0xffffu : 0xffffffu;
              for (int i = 0; i < 40; ++i) {
                const int x = int(pokes.next() % kW), y = int(pokes.next() % kH);
                const uint32_t k = pokes.next() % 6;
                depth.store(x, y, format == DepthFormat::D32F ? d32[k] : k % 2 ? top : 0u);
              }
            }
            st.depth = {true, func, false, false};
            st.blend[0] = BlendState::separate(BlendEquation::Add, BlendEquation::Add, BlendFactor::One, BlendFactor::One,
                                               BlendFactor::One, BlendFactor::One);
            FragmentProgram program = programOf(shade);
            program.readsDepth = readsDepth;
            const uint64_t nanBefore = nanDepths.load();
            stats[perFragment] = r.draw(fb, st, transparent, program);
            if (readsDepth || perFragment) CHECK(nanDepths.load() == nanBefore);  // depths where promised
            bytes[perFragment] = attachmentBytes(sum, depth);
          }
          INFO("tile " << tile << " " << toString(format) << " " << toString(func) << " poked " << poked << " reads depth "
                        << readsDepth);
          size_t differing = 0;  // counted, not printed: a failure would print 200 KB of bytes
          for (size_t i = 0; i < bytes[0].size(); ++i) differing += bytes[0][i] != bytes[1][i];
          CHECK(bytes[0].size() == bytes[1].size());
          CHECK(differing == 0);
          CHECK(stats[0].fragmentsRasterized == stats[1].fragmentsRasterized);
          CHECK(stats[0].fragmentsShaded == stats[1].fragmentsShaded);
          CHECK(stats[0].fragmentsDepthFailed == stats[1].fragmentsDepthFailed);
          CHECK(stats[0].fragmentsWritten == stats[1].fragmentsWritten);
          passed += stats[0].fragmentsShaded;
          failed += stats[0].fragmentsDepthFailed;
          ++compared;
        }
  CHECK(compared == 120);
  CHECK(passed > 400000);
  CHECK(failed > 400000);
  CHECK(nanDepths.load() > 100000);  // runs that surely pass skipped the window depth
}

// An RGBA16F target cleared to a colour, with a D24 depth buffer, OVER and a depth test that does
// not write: what the draw-sequence tests draw into (OVER does not commute, so the order shows).
struct OverTarget {
  Image color{makeFormat(FormatId::RGBA16F), W, H};
  DepthBuffer depth{DepthFormat::D24, W, H};
  Framebuffer fb;
  PipelineState state;
  OverTarget() {
    color.clear({0.1f, 0.2f, 0.3f, 1}, exactProfile());
    fb.color[0] = &color, fb.depth = &depth;
    state.blend[0] = kOver;
    state.depth = {true, CompareFunc::LEqual, false, false};
  }
  OverTarget(const OverTarget&) = delete;
  std::vector<uint8_t> bytes() const { return {color.bytes().begin(), color.bytes().end()}; }
};

TEST_CASE("fragment ops: a draw sequence gives the bytes of its draws one after another", "[fragment]") {
  // Renderer::drawSequence runs every draw tile by tile; OVER does not commute, so the bytes are
  // those of separate draw() calls only if each pixel still sees the draws in order. drawId
  // reaches the shader (here it picks the colour), on the span and the per-fragment paths.
  std::vector<Geometry> geometries;
  for (uint32_t d = 0; d < 5; ++d) geometries.push_back(overlappingTriangles(40, 100 + d));
  std::atomic<int> wrongDrawId{0};  // counted in the shaders, which run on the renderer's threads
  auto program = [&wrongDrawId](uint32_t drawId) {
    return programOf([drawId, &wrongDrawId](const FragmentInput& in, FragmentOutput& o) {
      if (in.drawId != drawId) wrongDrawId.fetch_add(1, std::memory_order_relaxed);
      o.write(0, colorOf(in.primitiveId * 7 + drawId * 3));
    });
  };
  for (bool perFragment : {false, true}) {
    std::vector<uint8_t> bytes[2];
    DrawStats stats[2];
    for (int sequence = 0; sequence < 2; ++sequence) {
      Renderer r(RendererOptions{3, 8, perFragment});
      OverTarget target;
      if (sequence) {
        std::vector<Renderer::DrawCall> draws;
        for (uint32_t d = 0; d < 5; ++d) draws.push_back({&geometries[d], program(10 + d), 10 + d});
        stats[1] = r.drawSequence(target.fb, target.state, draws);
      } else {
        for (uint32_t d = 0; d < 5; ++d)
          stats[0] += r.drawSequence(target.fb, target.state, {Renderer::DrawCall{&geometries[d], program(10 + d), 10 + d}});
      }
      bytes[sequence] = target.bytes();
    }
    INFO("per fragment " << perFragment);
    CHECK(bytes[0] == bytes[1]);
    CHECK(stats[0].fragmentsWritten == stats[1].fragmentsWritten);
    CHECK(stats[0].trianglesRasterized == stats[1].trianglesRasterized);
    CHECK(stats[1].fragmentsWritten > 0);
  }
  CHECK(wrongDrawId.load() == 0);
}

TEST_CASE("fragment ops: a draw sequence in bands gives the bytes of whole tiles, each band begun and ended on its worker", "[fragment]") {
  // TileBands: each band of a tile is drawn through every draw before the next band; `begin` comes
  // before the band's first fragment and `end` after its last, on the worker that shades them (the
  // A-buffer stores a band's lists between the two and resolves them in `end` without a lock).
  // OVER does not commute, so the bytes are those of whole tiles only if each pixel still sees
  // the draws in order. Bands of 3 rows do not divide the tiles of 8 (nor the last tile row of 4).
  std::vector<Geometry> geometries;
  for (uint32_t d = 0; d < 5; ++d) geometries.push_back(overlappingTriangles(40, 300 + d));
  const FragmentProgram plain = programOf([](const FragmentInput& in, FragmentOutput& o) {
    o.write(0, colorOf(in.primitiveId * 7 + in.drawId * 3));
  });
  auto draw = [&](bool perFragment, const FragmentProgram& program, const TileBands& bands) {
    Renderer r(RendererOptions{3, 8, perFragment});
    OverTarget target;
    std::vector<Renderer::DrawCall> draws;
    for (uint32_t d = 0; d < 5; ++d) draws.push_back({&geometries[d], program, d});
    const DrawStats stats = r.drawSequence(target.fb, target.state, draws, bands);
    return std::make_pair(target.bytes(), stats.fragmentsShaded);
  };
  for (bool perFragment : {false, true}) {
    INFO("per fragment " << perFragment);
    std::vector<int> shaded(size_t(W) * H, 0), shadedAtBegin(size_t(W) * H, -1), shadedAtEnd(size_t(W) * H, -1);
    std::vector<int> begun(size_t(W) * H, 0), ended(size_t(W) * H, 0);
    std::atomic<int> outsideBand{0}, unbalanced{0}, bandsDrawn{0};
    static thread_local const TileRect* open = nullptr;  // the band this worker is drawing
    const FragmentProgram program = programOf([&](const FragmentInput& in, FragmentOutput& o) {
      if (!open || in.x < open->x0 || in.x >= open->x1 || in.y < open->y0 || in.y >= open->y1)
        outsideBand.fetch_add(1, std::memory_order_relaxed);
      ++shaded[size_t(in.y) * W + size_t(in.x)];
      o.write(0, colorOf(in.primitiveId * 7 + in.drawId * 3));
    });
    auto each = [](const TileRect& r, auto&& f) {
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) f(size_t(y) * W + size_t(x));
    };
    TileBands bands;
    bands.rows = 3;
    std::vector<uint32_t> reaching(size_t(W) * H, 0);
    bands.begin = [&](const TileRect& r, uint32_t triangles) {
      if (open) unbalanced.fetch_add(1, std::memory_order_relaxed);
      each(r, [&](size_t p) { reaching[p] = triangles; });
      open = new TileRect(r);
      if (r.y1 - r.y0 > 3) unbalanced.fetch_add(1, std::memory_order_relaxed);
      each(r, [&](size_t p) { ++begun[p], shadedAtBegin[p] = shaded[p]; });
    };
    bands.end = [&](const TileRect& r) {
      if (!open || open->x0 != r.x0 || open->y0 != r.y0 || open->x1 != r.x1 || open->y1 != r.y1)
        unbalanced.fetch_add(1, std::memory_order_relaxed);
      delete std::exchange(open, nullptr);
      bandsDrawn.fetch_add(1, std::memory_order_relaxed);
      each(r, [&](size_t p) { ++ended[p], shadedAtEnd[p] = shaded[p]; });
    };
    const auto [banded, bandedShaded] = draw(perFragment, program, bands);
    const auto [whole, wholeShaded] = draw(perFragment, plain, {});
    CHECK(banded == whole);
    CHECK(bandedShaded == wholeShaded);
    CHECK(outsideBand.load() == 0);
    CHECK(unbalanced.load() == 0);
    CHECK(bandsDrawn.load() == 3 * (3 + 3 + 2));  // 24×20: 3 × 3 tiles of 8 (the last row of 4), bands 3+3+2, 3+3+2, 3+1
    CHECK(begun == std::vector<int>(size_t(W) * H, 1));
    CHECK(ended == begun);
    CHECK(shadedAtBegin == std::vector<int>(size_t(W) * H, 0));
    CHECK(shadedAtEnd == shaded);
    // The triangles binned to the band's tile bound every pixel's fragments; none are clipped
    // here, so no tile gets more than the draws' 200.
    int above = 0;
    for (size_t p = 0; p < shaded.size(); ++p) above += uint32_t(shaded[p]) > reaching[p];
    CHECK(above == 0);
    CHECK(*std::max_element(reaching.begin(), reaching.end()) <= 200u);
    uint64_t total = 0;
    for (int n : shaded) total += uint64_t(n);
    CHECK(total == bandedShaded);
    CHECK(total > uint64_t(W) * H);
  }
}

// Framebuffer::clearColor and clearDepth: a draw's clears, applied tile by tile where the tiles
// cover the framebuffer (the tile loop), everywhere first under a smaller viewport, and before a
// full-screen pass. The oracle is Image::clear and DepthBuffer::clear (whole-buffer fills) before
// the same draw. Each attachment starts from other bits, so a texel the draw's clear missed keeps
// them and shows; a draw of no triangles must still clear everything.
TEST_CASE("fragment ops: a draw's clears give the bits of clearing first, then drawing", "[fragment]") {
  const Geometry g = overlappingTriangles(30, 7);
  const FragmentProgram program = programOf([](const FragmentInput& in, FragmentOutput& o) {
    o.write(0, colorOf(in.primitiveId));
    o.write(1, colorOf(in.primitiveId + 5));
  });
  const glm::vec4 clear0{0.25f, 0.5f, 1.0f / 3.0f, 0.75f}, clear1{0.1f, -2.0f, 3.5f, 1.0f};
  PipelineState st;
  st.blend[0] = st.blend[1] = kOver;
  st.depth = {true, CompareFunc::Less, true, false};
  for (int mode = 0; mode < 4; ++mode) {  // triangles, no triangles, triangles in a viewport, full-screen
    std::vector<uint8_t> bytes[2];
    for (int byDraw = 0; byDraw < 2; ++byDraw) {
      Renderer r(RendererOptions{3, 8});
      Image a(makeFormat(FormatId::RGBA8), W, H), b(makeFormat(FormatId::RGBA16F), W, H);
      DepthBuffer depth(DepthFormat::D24, W, H);
      a.clear({0.9f, 0.8f, 0.7f, 0.6f}, exactProfile());
      b.clear({5, 6, 7, 8}, exactProfile());
      depth.clear(0.5);
      Framebuffer fb;
      fb.color[0] = &a, fb.color[1] = &b, fb.depth = &depth;
      if (byDraw) {
        fb.clearColor[0] = clear0, fb.clearColor[1] = clear1, fb.clearDepth = 1.0;
      } else {
        a.clear(clear0, st.profile), b.clear(clear1, st.profile), depth.clear(1.0);
      }
      PipelineState s = st;
      if (mode == 2) s.viewport = {3, 2, 13, 11};
      if (mode == 3) r.drawFullscreen(fb, s, program);
      else r.drawSequence(fb, s, mode == 1 ? std::vector<Renderer::DrawCall>{} : std::vector<Renderer::DrawCall>{{&g, program, 0}});
      CHECK_FALSE(fb.clearColor[0].has_value());  // taken by the draw
      CHECK_FALSE(fb.clearDepth.has_value());
      bytes[byDraw] = attachmentBytes(a, depth);
      bytes[byDraw].insert(bytes[byDraw].end(), b.bytes().begin(), b.bytes().end());
    }
    INFO("mode " << mode);
    CHECK(bytes[0] == bytes[1]);
  }
  Renderer r(RendererOptions{1, 8});
  Image a(makeFormat(FormatId::RGBA8), W, H);
  Framebuffer fb;
  fb.color[0] = &a;
  fb.clearColor[1] = clear1;  // no attachment 1
  CHECK_THROWS_WITH(r.drawSequence(fb, st, {}), Catch::Contains("colour target 1"));
  fb.clearColor[1].reset();
  fb.clearDepth = 1.0;
  CHECK_THROWS_WITH(r.drawSequence(fb, st, {}), Catch::Contains("depth clear"));
}

TEST_CASE("fragment ops: a shader's declared depth test discards unshaded, with the shader's bits and counts", "[fragment]") {
  // FragmentProgram::discardTest declares a test the shader applies itself (depth peeling's
  // "behind the previous layer"). The oracle is the same program without the declaration: the
  // same colour and depth bytes and the same counters (discarded fragments count as shaded) for
  // each depth format and compare function, on both paths; on the span path the shader runs on
  // fewer fragments.
  const Geometry g = overlappingTriangles(160, 29);
  int compared = 0, fewer = 0;
  for (DepthFormat format : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F})
    for (CompareFunc func : {CompareFunc::Greater, CompareFunc::GEqual, CompareFunc::Less, CompareFunc::LEqual})
      for (bool perFragment : {false, true}) {
        // The shader's own test reads a buffer of scattered depths over the triangles' range.
        DepthBuffer previous(format, W, H);
        test::BitStream rng(uint32_t(format) * 8 + uint32_t(func));
        for (int y = 0; y < H; ++y)
          for (int x = 0; x < W; ++x) previous.store(x, y, encodeDepth(rng.uniform(0.0f, 1.0f), format));
        const ShaderDepthTest test{&previous, func};
        std::atomic<uint64_t> invocations[2] = {0, 0};
        std::vector<uint8_t> bytes[2];
        DrawStats stats[2];
        for (int declared = 0; declared < 2; ++declared) {
          std::atomic<uint64_t>& calls = invocations[declared];
          const auto shader = [&](const FragmentInput& in, FragmentOutput& o) {
            calls.fetch_add(1, std::memory_order_relaxed);
            if (!depthTestPasses(test.func, encodeDepth(in.depth, format), previous.load(in.x, in.y), format))
              return o.discard();
            if ((in.primitiveId + uint32_t(in.x)) % 5 == 0) return o.discard();
            o.write(0, colorOf(in.primitiveId));
          };
          Renderer r(RendererOptions{2, 8, perFragment});
          Image a(makeFormat(FormatId::RGBA8), W, H);
          a.clear({0.1f, 0.2f, 0.3f, 1}, exactProfile());
          DepthBuffer depth(DepthFormat::D24, W, H);  // the pass's own depth test: LESS, written
          depth.clear(0.8);
          Framebuffer fb;
          fb.color[0] = &a, fb.depth = &depth;
          PipelineState st;
          st.blend[0] = kOver;
          st.depth = {true, CompareFunc::Less, true, false};
          FragmentProgram program = programOf(shader, true, false, false, true);
          if (declared) program.discardTest = test;
          stats[declared] = r.draw(fb, st, g, program);
          bytes[declared] = attachmentBytes(a, depth);
        }
        INFO(toString(format) << " " << toString(func) << " per fragment " << perFragment);
        CHECK(bytes[0] == bytes[1]);
        CHECK(stats[0].fragmentsShaded == stats[1].fragmentsShaded);
        CHECK(stats[0].fragmentsDiscarded == stats[1].fragmentsDiscarded);
        CHECK(stats[0].fragmentsWritten == stats[1].fragmentsWritten);
        CHECK(stats[0].fragmentsWritten > 0);
        CHECK(stats[1].fragmentsDiscarded > stats[1].fragmentsWritten / 4);
        if (perFragment) CHECK(invocations[1] == invocations[0]);  // the oracle path ignores the declaration
        else fewer += invocations[1] < invocations[0];
        ++compared;
      }
  CHECK(compared == 24);
  CHECK(fewer == 12);
}
