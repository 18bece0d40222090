// The shader interface's batch forms (oitref/core/shader.h): a FragmentBatch's in[i] is the fragment
// its arrays describe, and a FragmentBatchOutput holds what a FragmentOutput would, for each
// fragment of the batch. The pipeline tests compare whole frames of both paths; these pin the
// views themselves, field by field.
#include <catch2/catch.hpp>

#include <cstring>
#include <iterator>

#include "oitref/core/format.h"
#include "oitref/core/image.h"
#include "oitref/core/shader.h"

using namespace oitref;

TEST_CASE("shader: a FragmentBatch's in[i] is fragment i of its arrays, attributes read as rows") {
  constexpr int N = FragmentBatch::kCapacity, A = 3;
  int x[N];
  float depth[N], view[N], rows[A * N];
  for (int i = 0; i < N; ++i) {
    x[i] = 7 + 2 * i;
    depth[i] = float(i) / 128.0f;
    view[i] = 1.0f + float(i);
    for (int k = 0; k < A; ++k) rows[k * N + i] = float(100 * k + i);
  }
  FragmentBatch batch;
  batch.count = 40;
  batch.y = 5;
  batch.x = x, batch.depth = depth, batch.viewDepth = view, batch.attributes = rows;
  batch.attributeCount = A, batch.attributeStride = N;
  batch.frontFacing = false, batch.primitiveId = 9, batch.drawId = 4;
  for (int i = 0; i < batch.count; ++i) {
    const FragmentInput in = batch[i];
    INFO("fragment " << i);
    CHECK(in.x == 7 + 2 * i);
    CHECK(in.y == 5);
    CHECK(in.fragCoord == glm::vec2(float(7 + 2 * i) + 0.5f, 5.5f));
    CHECK(in.depth == float(i) / 128.0f);
    CHECK(in.viewDepth == 1.0f + float(i));
    CHECK((!in.frontFacing && in.primitiveId == 9 && in.drawId == 4 && in.attributeCount == A));
    CHECK(in.vec3At(0) == glm::vec3(float(i), float(100 + i), float(200 + i)));
    // A batch of one made from it reads the same fragment back.
    const FragmentInput again = FragmentBatch::of(in)[0];
    CHECK((again.x == in.x && again.y == in.y && again.depth == in.depth && again.viewDepth == in.viewDepth));
    CHECK(again.vec3At(0) == in.vec3At(0));
  }
}

TEST_CASE("shader: a FragmentBatchOutput holds what a FragmentOutput holds, per fragment") {
  // What each fragment's shader does, applied to a FragmentOutput and, through view/finish and
  // through the batch's own writes, to the batch.
  auto shade = [](int i, auto&& write, auto&& discard, auto&& setDepth) {
    if (i % 5 == 0) return discard();
    write(0, glm::vec4(float(i), 0.5f, -1.0f, 2.0f));
    if (i % 3 == 0) write(2, glm::vec4(0.25f * float(i)));
    if (i % 4 == 1) setDepth(float(i) / 64.0f);
  };
  constexpr int N = FragmentBatchOutput::kCapacity;
  FragmentBatchOutput viewed, direct;
  viewed.reset(N), direct.reset(N);
  for (int i = 0; i < N; ++i) {
    FragmentOutput o = viewed.view(i);
    shade(i, [&](int t, const glm::vec4& c) { o.write(t, c); }, [&] { o.discard(); }, [&](float z) { o.setDepth(z); });
    viewed.finish(i, o);
    shade(i, [&](int t, const glm::vec4& c) { direct.write(i, t, c); }, [&] { direct.discard(i); },
          [&](float z) { direct.setDepth(i, z); });
  }
  for (int i = 0; i < N; ++i) {
    FragmentOutput expected;
    shade(i, [&](int t, const glm::vec4& c) { expected.write(t, c); }, [&] { expected.discard(); },
          [&](float z) { expected.setDepth(z); });
    INFO("fragment " << i);
    for (const FragmentBatchOutput* b : {&viewed, &direct}) {
      CHECK(b->writtenMask(i) == expected.writtenMask());
      CHECK(b->discarded(i) == expected.discarded());
      CHECK(b->depthWritten(i) == expected.depthWritten());
      if (expected.depthWritten()) CHECK(b->depth(i) == expected.depth());
      for (unsigned t = expected.writtenMask(); t; t &= t - 1) {
        CHECK(b->color(__builtin_ctz(t), i) == expected.color(__builtin_ctz(t)));
        CHECK(b->colors(__builtin_ctz(t))[i] == expected.color(__builtin_ctz(t)));
      }
      FragmentOutput back;  // load: the batch's fragment into a FragmentOutput again
      b->load(i, back);
      CHECK(back.writtenMask() == expected.writtenMask());
      CHECK(back.discarded() == expected.discarded());
      for (unsigned t = expected.writtenMask(); t; t &= t - 1)
        CHECK(back.color(__builtin_ctz(t)) == expected.color(__builtin_ctz(t)));
    }
  }
  viewed.reset(N);
  for (int i = 0; i < N; ++i) CHECK((viewed.writtenMask(i) == 0 && !viewed.discarded(i) && !viewed.depthWritten(i)));
}

TEST_CASE("shader: texelsOf and redTexelsOf give fetchTexels's bits, in place or fetched") {
  // Runs (in place for RGBA32F and R32F) and scattered columns (fetched), every format family,
  // with fp32 payloads that a conversion would change: a signalling NaN, −0, a denormal.
  const uint32_t specials[] = {0x7f800001u, 0x80000000u, 0x00000001u, 0x3f800000u, 0xc1234567u, 0x7f800000u};
  for (const char* name : {"rgba32f", "r32f", "rg32f", "rgba16f", "r16f", "rgba8", "r8"}) {
    const Format f = parseFormat(name);
    Image image(f, 9, 2);
    for (size_t i = 0; i < image.sizeBytes(); ++i)
      image.texel(0, 0)[i] = uint8_t(specials[(i / 4) % std::size(specials)] >> (8 * (i % 4)));
    int run[6] = {2, 3, 4, 5, 6, 7}, scattered[6] = {8, 0, 3, 3, 5, 1};
    for (bool isRun : {true, false}) {
      FragmentBatch in;
      in.count = 6, in.y = 1, in.run = isRun, in.x = isRun ? run : scattered;
      glm::vec4 want[FragmentBatch::kCapacity], scratch[FragmentBatch::kCapacity];
      float redScratch[FragmentBatch::kCapacity];
      fetchTexels(image, in, want);
      const glm::vec4* got = texelsOf(image, in, scratch);
      const float* reds = redTexelsOf(image, in, redScratch);
      INFO(name << (isRun ? " run" : " scattered"));
      // In place exactly for the runs of the fp32 layouts that hold what fetch gives.
      CHECK((got != scratch) == (isRun && f == parseFormat("rgba32f")));
      CHECK((reds != redScratch) == (isRun && f == parseFormat("r32f")));
      for (int i = 0; i < in.count; ++i) {
        CHECK(std::memcmp(&got[i], &want[i], sizeof want[i]) == 0);
        CHECK(std::memcmp(&reds[i], &want[i].r, sizeof reds[i]) == 0);
      }
    }
  }
}
