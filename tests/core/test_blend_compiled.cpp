// The blend kernels compiled per draw for the methods' blend states (blend/method_blend_states.h)
// against the general kernels, which make every decision per fragment: same stored bits.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#if defined(__x86_64__)
#include <xmmintrin.h>
#endif

#include "blend/method_blend_states.h"
#include "blend/target_blender.h"
#include "support.h"

using namespace oitref;

namespace {

// Inputs that reach every rule: specials, denormals (DAZ), values whose products are tiny (FTZ),
// exactly ±2^-126, UNORM edges, and ordinary random values.
float interesting(test::BitStream& rng) {
  static const float specials[] = {NAN,     -NAN,      INFINITY,  -INFINITY, 0.0f,        -0.0f,       1e-40f, -1e-40f,
                                   0x1p-126f, -0x1p-126f, 0x1p-64f, 0x1p-63f, 65520.0f, 1.0f, 0.5f, 1.0f / 255.0f,
                                   0.99999994f, 1.0000001f};
  switch (rng.next() % 4) {
    case 0: return specials[rng.next() % (sizeof specials / sizeof specials[0])];
    case 1: return rng.uniform(0.0f, 1.0f);
    case 2: return rng.uniform(-2.0f, 3.0f);
    default: {  // any bit pattern
      const uint32_t bits = rng.next();
      float f;
      std::memcpy(&f, &bits, 4);
      return f;
    }
  }
}

}  // namespace

TEST_CASE("blend: kernels compiled for the methods' blend states give the general kernels' bits", "[blend]") {
  test::BitStream rng(2026);
  const char* formats[] = {"rgba8", "rg8", "r8", "rgba16", "rgb10a2", "rgba16f", "rg16f", "r16f",
                           "rgba32f", "rg32f", "r32f", "r11g11b10f"};
  int compared = 0;
  for (const char* name : formats) {
    const Format f = parseFormat(name);
    for (const Profile& p : {exactProfile(), llvmpipeProfile(), parseProfile("llvmpipe,fma=off"), nvidiaProfile()})
      for (const BlendState& state : detail::states::kMethodBlendStates)
        for (bool smallFloatBound : {false, true})
          for (int i = 0; i < 400; ++i) {
            glm::vec4 src, constant;
            for (int k = 0; k < 4; ++k) src[k] = interesting(rng), constant[k] = rng.uniform(-0.5f, 1.5f);
            uint8_t compiled[16], general[16];
            for (int b = 0; b < 16; ++b) compiled[b] = uint8_t(rng.next());
            if (i % 2 == 0 && !f.isUnorm())  // a destination of interesting values
              for (int k = 0; k < f.channels; ++k) {
                const float v = interesting(rng);
                if (f.bytesPerChannel() == 4) std::memcpy(compiled + 4 * k, &v, 4);
              }
            std::memcpy(general, compiled, 16);
            detail::TargetBlender(f, state, constant, p, true, smallFloatBound).blend(src, compiled);
            detail::TargetBlender(f, state, constant, p, false, smallFloatBound).blend(src, general);
            if (std::memcmp(compiled, general, size_t(f.bytesPerTexel())) != 0)
              FAIL(name << " " << p.describe() << " " << state.describe() << " small-float bound " << smallFloatBound
                        << ": compiled " << texelBitsToString(f, compiled) << ", general "
                        << texelBitsToString(f, general));
            ++compared;
          }
  }
  CHECK(compared == 12 * 4 * int(std::size(detail::states::kMethodBlendStates)) * 2 * 400);
}

// TargetBlender::blendBatch runs eight lanes at a time — the llvmpipe float model (two rgba, four
// rg or eight r pixels per call; AVX2), the exact float kernels (two rgba, four rg or eight r
// pixels), the exact and llvmpipe-UNORM fast kernels of RGBA8 (two pixels) —
// with the pixels after the last whole group as a padded group (the float kernels) or one at a
// time: every batch size (past the llvmpipe model's chunk of 64 too, the padded group joining a
// first or a later chunk), the methods' states (compiled kernels) and random states (the general
// functions), against the per-fragment general kernel. blendRun, the same pixels as one run of consecutive
// texels (a group's texels loaded and stored at once), against it too.
TEST_CASE("blend: batches of eight lanes give the per-fragment kernel's bits", "[blend]") {
  test::BitStream rng(77);
  std::vector<BlendState> states(std::begin(detail::states::kMethodBlendStates), std::end(detail::states::kMethodBlendStates));
  // Blending disabled (the conversion alone: the composites' final RGBA8), all channels and some.
  states.push_back(BlendState{});
  BlendState someChannels;
  someChannels.writeMask = 0x5;
  states.push_back(someChannels);
  for (int i = 0; i < 40; ++i)
    states.push_back(BlendState::separate(BlendEquation(rng.next() % 5), BlendEquation(rng.next() % 5),
                                          BlendFactor(rng.next() % 15), BlendFactor(rng.next() % 15),
                                          BlendFactor(rng.next() % 15), BlendFactor(rng.next() % 15)));
  int compared = 0;
  for (const char* name : {"rgba16f", "rg16f", "r16f", "rgba32f", "rg32f", "r32f", "rgba8", "rg8", "r8"}) {
    const Format f = parseFormat(name);
    const int bytes = f.bytesPerTexel();
    for (const Profile& p : {llvmpipeProfile(), parseProfile("llvmpipe,fma=off"), exactProfile(),
                             parseProfile("exact,unorm=fp32"), parseProfile("exact,unorm=nvidia"), parseProfile("exact,fp16=rtz")})
      for (const BlendState& state : states)
        for (bool smallFloatBound : {false, true}) {
          glm::vec4 constant;
          for (int k = 0; k < 4; ++k) constant[k] = interesting(rng);
          const detail::TargetBlender batch(f, state, constant, p, true, smallFloatBound);
          const detail::TargetBlender single(f, state, constant, p, false, smallFloatBound);
          for (int n : {1, 2, 3, 7, 8, 9, 17, 70, 71, 135}) {
            std::vector<glm::vec4> sources(static_cast<size_t>(n));
            std::vector<uint8_t> batched(size_t(n * bytes)), expected;
            for (glm::vec4& s : sources)
              for (int k = 0; k < 4; ++k) s[k] = interesting(rng);
            for (int i = 0; i < n * bytes / 4; ++i) {  // fp32 channels, two fp16 ones or four UNORM8 ones
              const float v = interesting(rng);
              std::memcpy(&batched[size_t(4 * i)], &v, 4);
            }
            for (int i = (n * bytes / 4) * 4; i < n * bytes; ++i) batched[size_t(i)] = uint8_t(rng.next());
            expected = batched;
            std::vector<uint8_t> run = batched;
            std::vector<const glm::vec4*> sourcePointers;
            std::vector<uint8_t*> texels;
            for (int i = 0; i < n; ++i) {
              sourcePointers.push_back(&sources[size_t(i)]);
              texels.push_back(&batched[size_t(i * bytes)]);
              single.blend(sources[size_t(i)], &expected[size_t(i * bytes)]);
            }
            batch.blendBatch(sourcePointers.data(), texels.data(), n);
            batch.blendRun(sources.data(), run.data(), n);
            for (int i = 0; i < n; ++i)
              for (const auto& [kind, result] : {std::pair{"batch", &batched}, std::pair{"run", &run}})
                if (std::memcmp(&(*result)[size_t(i * bytes)], &expected[size_t(i * bytes)], size_t(bytes)) != 0)
                  FAIL(name << " " << p.describe() << " " << state.describe() << " n " << n << " pixel " << i << ": "
                            << kind << " " << texelBitsToString(f, &(*result)[size_t(i * bytes)]) << ", per fragment "
                            << texelBitsToString(f, &expected[size_t(i * bytes)]));
            ++compared;
          }
        }
  }
  CHECK(compared == 9 * 6 * int(states.size()) * 2 * 10);
}

// llvmpipe's UNORM8 integer blend has two compiled batches per method state: the build's ISA (one
// pixel per step) and AVX2 (RGBA8 two pixels per step), chosen by the CPU. Both, whatever this
// machine chooses, against the general per-texel function, every batch size from 1 to 9.
TEST_CASE("blend: both ISA variants of llvmpipe's UNORM8 batch give the general function's bits", "[blend]") {
  test::BitStream rng(78);
  int compared = 0;
  for (const char* name : {"rgba8", "rg8", "r8"}) {
    const Format f = parseFormat(name);
    const int bytes = f.bytesPerTexel();
    for (const BlendState& state : detail::states::kMethodBlendStates)
      for (const UnormRounding rounding : {llvmpipeProfile().unorm, exactProfile().unorm}) {
        glm::vec4 constant;
        for (int k = 0; k < 4; ++k) constant[k] = rng.uniform(-0.5f, 1.5f);
        const detail::UnormIntegerPlan plan = detail::planUnormInteger(f, state, constant, rounding, (1u << f.channels) - 1);
        const detail::UnormIntegerBlendFn general = detail::unormIntegerBlendFor(plan, false);
        for (const bool allowAvx2 : {false, true}) {
          const detail::UnormIntegerBatchFn batch = detail::unormIntegerBatchFor(plan, true, allowAvx2);
          for (int n = 1; n <= 9; ++n) {
            std::vector<glm::vec4> sources(static_cast<size_t>(n));
            std::vector<uint8_t> batched(size_t(n * bytes));
            for (glm::vec4& s : sources)
              for (int k = 0; k < 4; ++k) s[k] = interesting(rng);
            for (uint8_t& b : batched) b = uint8_t(rng.next());
            std::vector<uint8_t> expected = batched;
            std::vector<const glm::vec4*> sourcePointers;
            std::vector<uint8_t*> texels;
            for (int i = 0; i < n; ++i) {
              sourcePointers.push_back(&sources[size_t(i)]);
              texels.push_back(&batched[size_t(i * bytes)]);
              general(plan, sources[size_t(i)], &expected[size_t(i * bytes)]);
            }
            batch(plan, sourcePointers.data(), texels.data(), n);
            INFO(name << " " << state.describe() << " AVX2 allowed " << allowAvx2 << " n " << n);
            CHECK(batched == expected);
            ++compared;
          }
        }
      }
  }
  CHECK(compared == 3 * int(std::size(detail::states::kMethodBlendStates)) * 2 * 2 * 9);
}

// blendRun leaves alone the pixels whose blend keeps their texel's bits (TargetBlender::keptPixels:
// the composite states with the source (+0, +0, +0, 1)). Against the per-fragment general kernel,
// which blends every pixel: runs where half the sources are exactly that one, the others near it
// (−0, an alpha one ulp below 1) or anything, over destinations with −0, NaN, infinities and
// denormals, in every profile (the `nvidia` profile and the OVER state never skip; the others
// must skip some pixels, or the test would not reach the skipping).
TEST_CASE("blend: a run skips exactly the pixels whose bits the composite keeps", "[blend]") {
  test::BitStream rng(79);
  const glm::vec4 kept(0.0f, 0.0f, 0.0f, 1.0f);
  int compared = 0;
  for (const char* name : {"rgba8", "rg8", "r8", "rgba16", "rgba16f", "r16f", "rgba32f", "rg32f", "r32f"}) {
    const Format f = parseFormat(name);
    const int bytes = f.bytesPerTexel();
    for (const Profile& p : {llvmpipeProfile(), parseProfile("llvmpipe,fma=off"), exactProfile(), parseProfile("exact,unorm=fp32"),
                             parseProfile("exact,unorm=nvidia"), nvidiaProfile()})
      for (const BlendState& state : {detail::states::kComposite, detail::states::kPremultipliedOntoBackground, detail::states::kOver})
        for (bool smallFloatBound : {false, true}) {
          const detail::TargetBlender run(f, state, glm::vec4(0.5f), p, true, smallFloatBound);
          const detail::TargetBlender single(f, state, glm::vec4(0.5f), p, false, smallFloatBound);
          const int n = 200;
          std::vector<glm::vec4> sources(static_cast<size_t>(n));
          for (glm::vec4& s : sources) {
            switch (rng.next() % 6) {
              case 0: case 1: case 2: s = kept; break;
              case 3: s = glm::vec4(-0.0f, 0.0f, 0.0f, 1.0f); break;
              case 4: s = glm::vec4(0.0f, 0.0f, 0.0f, 0.99999994f); break;
              default:
                for (int k = 0; k < 4; ++k) s[k] = interesting(rng);
            }
          }
          std::vector<uint8_t> texels(size_t(n * bytes));
          for (int i = 0; i < n * bytes / 4; ++i) {  // fp32 channels, two fp16 ones or four 8-bit codes
            const float v = interesting(rng);
            std::memcpy(&texels[size_t(4 * i)], &v, 4);
          }
          for (int i = (n * bytes / 4) * 4; i < n * bytes; ++i) texels[size_t(i)] = uint8_t(rng.next());
          if (f.encoding() == ChannelEncoding::Half)  // fp16 −0, NaN and denormals in some texels
            for (int i = 0; i < n * bytes / 2; i += 7) {
              const uint16_t specials[] = {0x8000, 0x7e00, 0x0001, 0x83ff, 0x7c00, 0x0000};
              std::memcpy(&texels[size_t(2 * i)], &specials[rng.next() % 6], 2);
            }
          std::vector<uint8_t> expected = texels, got = texels;
          int keptPixels = 0;
          for (int i = 0; i < n; ++i) {
            single.blend(sources[size_t(i)], &expected[size_t(i * bytes)]);
            keptPixels += int(run.keptPixels(&sources[size_t(i)], &texels[size_t(i * bytes)], 1));
          }
          run.blendRun(sources.data(), got.data(), n);
          INFO(name << " " << p.describe() << " " << state.describe() << " small-float bound " << smallFloatBound);
          for (int i = 0; i < n; ++i)
            if (std::memcmp(&got[size_t(i * bytes)], &expected[size_t(i * bytes)], size_t(bytes)) != 0)
              FAIL("pixel " << i << ": run " << texelBitsToString(f, &got[size_t(i * bytes)]) << ", per fragment "
                            << texelBitsToString(f, &expected[size_t(i * bytes)]));
          const bool eligible = !(state == detail::states::kOver) && std::string(name) != "rgba16" &&
                                !(f.isUnorm() ? p.unormBlend == UnormBlend::Nvidia : p.floatBlend == FloatBlend::Nvidia);
          if (eligible) CHECK(keptPixels > 0);
          else CHECK(keptPixels == 0);
          ++compared;
        }
  }
  CHECK(compared == 9 * 6 * 3 * 2);
}

#if defined(__x86_64__)
// The llvmpipe float kernels blend chunks with DAZ and FTZ set in the MXCSR (llvmpipe's own mode)
// and put back the mode of the thread that made the blender: whatever that mode is (here
// rounding toward zero, the exception masks changed), the thread has it again after a run and a
// batch, and a blender made in the default mode leaves the default mode.
TEST_CASE("blend: llvmpipe's float kernels leave the thread's MXCSR as they found it", "[blend]") {
  const unsigned original = _mm_getcsr();
  for (unsigned mode : {original, (original & ~0x6000u) | 0x6000u, original & ~0x0080u}) {
    _mm_setcsr(mode);
    for (const char* name : {"rgba32f", "r32f"}) {
      const Format f = parseFormat(name);
      const detail::TargetBlender blender(f, detail::states::kAdditive, glm::vec4(0.0f), llvmpipeProfile(), true, false);
      std::vector<glm::vec4> sources(70, glm::vec4(0.25f, 1e-40f, -0.5f, 0.75f));
      std::vector<uint8_t> texels(70 * size_t(f.bytesPerTexel()), 0);
      std::vector<const glm::vec4*> sourcePointers;
      std::vector<uint8_t*> texelPointers;
      for (int i = 0; i < 70; ++i)
        sourcePointers.push_back(&sources[size_t(i)]), texelPointers.push_back(&texels[size_t(i * f.bytesPerTexel())]);
      blender.blendRun(sources.data(), texels.data(), 70);
      CHECK(_mm_getcsr() == mode);
      blender.blendBatch(sourcePointers.data(), texelPointers.data(), 70);
      CHECK(_mm_getcsr() == mode);
    }
  }
  _mm_setcsr(original);
}
#endif
