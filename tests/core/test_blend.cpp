// Blending: every factor and equation on every format against a reference written here from GL
// 4.6 tables 17.1 and 17.2 (factors as 4-vectors, exactly as the table lists them), with the
// result converted by the independent oracles (F16C or the enumerating minifloat oracle, the
// integer UNORM oracle). Plus hand-derived bit patterns for the edge cases.
#include <catch2/catch.hpp>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <cstring>

#include "blend/blend_unorm_integer.h"
#include "blend/target_blender.h"
#include "oitref/core/fp16.h"
#include "oitref/core/blend.h"
#include "oracles.h"
#include "support.h"

using namespace oitref;

namespace {

glm::vec4 clamp01(glm::vec4 v) {
  for (int i = 0; i < 4; ++i) v[i] = v[i] > 0.0f ? (v[i] < 1.0f ? v[i] : 1.0f) : 0.0f;
  return v;
}

// GL 4.6 table 17.2: (f_R, f_G, f_B, f_A) for each factor.
glm::vec4 tableFactor(BlendFactor f, glm::vec4 s, glm::vec4 d, glm::vec4 c) {
  const glm::vec4 one(1.0f);
  switch (f) {
    case BlendFactor::Zero: return glm::vec4(0.0f);
    case BlendFactor::One: return one;
    case BlendFactor::SrcColor: return s;
    case BlendFactor::OneMinusSrcColor: return one - s;
    case BlendFactor::DstColor: return d;
    case BlendFactor::OneMinusDstColor: return one - d;
    case BlendFactor::SrcAlpha: return glm::vec4(s.a);
    case BlendFactor::OneMinusSrcAlpha: return glm::vec4(1.0f - s.a);
    case BlendFactor::DstAlpha: return glm::vec4(d.a);
    case BlendFactor::OneMinusDstAlpha: return glm::vec4(1.0f - d.a);
    case BlendFactor::ConstantColor: return c;
    case BlendFactor::OneMinusConstantColor: return one - c;
    case BlendFactor::ConstantAlpha: return glm::vec4(c.a);
    case BlendFactor::OneMinusConstantAlpha: return glm::vec4(1.0f - c.a);
    case BlendFactor::SrcAlphaSaturate: {
      const float m = std::min(s.a, 1.0f - d.a);
      return {m, m, m, 1.0f};
    }
  }
  return glm::vec4(0.0f);
}

// GL 4.6 table 17.1, per channel, products rounded before the sum.
float tableEquation(BlendEquation e, float s, float d, float sf, float df) {
  volatile float a = s * sf, b = d * df;  // volatile: two separately rounded products, by construction
  switch (e) {
    case BlendEquation::Add: return a + b;
    case BlendEquation::Subtract: return a - b;
    case BlendEquation::ReverseSubtract: return b - a;
    case BlendEquation::Min: return std::isnan(s) ? d : std::isnan(d) ? s : (d < s ? d : s);
    case BlendEquation::Max: return std::isnan(s) ? d : std::isnan(d) ? s : (d > s ? d : s);
  }
  return 0;
}

glm::vec4 referenceBlend(const BlendState& st, glm::vec4 s, glm::vec4 d, glm::vec4 c, const Format& f) {
  if (f.isUnorm()) {
    s = clamp01(s);
    c = clamp01(c);
  }
  if (!f.hasAlpha()) d.a = 1.0f;
  const glm::vec4 sRgb = tableFactor(st.srcRgb, s, d, c), dRgb = tableFactor(st.dstRgb, s, d, c);
  const glm::vec4 sA = tableFactor(st.srcAlpha, s, d, c), dA = tableFactor(st.dstAlpha, s, d, c);
  glm::vec4 r;
  for (int i = 0; i < 3; ++i) r[i] = tableEquation(st.equationRgb, s[i], d[i], sRgb[i], dRgb[i]);
  r[3] = tableEquation(st.equationAlpha, s[3], d[3], sA[3], dA[3]);
  return f.isUnorm() ? clamp01(r) : r;
}

#if defined(__x86_64__)
__attribute__((target("f16c"))) uint32_t f16c(float v) { return _cvtss_sh(v, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC); }
#else
uint32_t f16c(float) { return 0; }
#endif

// Expected stored bits of channel c under the exact profile; nullopt-like -1 for "any NaN".
int64_t expectedChannelBits(const Format& f, int c, float v) {
  switch (f.encoding()) {
    case ChannelEncoding::Unorm: return test::oracleUnorm(v, f.unormBits(c));
    case ChannelEncoding::Float32: return test::toBits(v);
    case ChannelEncoding::Half:
      if (cpuHasF16C()) return f16c(v);
      [[fallthrough]];
    default: {
      const MinifloatSpec spec = f.encoding() == ChannelEncoding::Half ? kHalfSpec
                                 : f.encoding() == ChannelEncoding::PackedFloat11_10 ? (c < 2 ? kFloat11Spec : kFloat10Spec)
                                                                                     : f.minifloat;
      if (std::isnan(v)) return -1;
      if (std::isinf(v) && spec.specials == FloatSpecials::Ieee && (v > 0 || spec.isSigned))
        return (v < 0 ? 1u << (spec.exponentBits + spec.mantissaBits) : 0) |
               (((1u << spec.exponentBits) - 1) << spec.mantissaBits);
      if (std::isinf(v)) return encodeMinifloat(v, spec, Rounding::NearestEven);  // covered by minifloat tests
      return test::MinifloatOracle(spec).encode(v, Rounding::NearestEven);
    }
  }
}

// Channel c's bits from the texel, by the layouts of GL 4.6 table 8.8 written out again here.
uint32_t storedChannelBits(const Format& f, const uint8_t* t, int c) {
  uint32_t w = 0;
  if (f.id == FormatId::RGB10A2) {
    std::memcpy(&w, t, 4);
    return c < 3 ? (w >> (10 * c)) & 0x3ff : w >> 30;
  }
  if (f.id == FormatId::R11G11B10F) {
    std::memcpy(&w, t, 4);
    return c == 0 ? w & 0x7ff : c == 1 ? (w >> 11) & 0x7ff : w >> 22;
  }
  const int bytes = f.bytesPerChannel();
  std::memcpy(&w, t + c * bytes, size_t(bytes));
  return w;
}

std::vector<Format> allFormats() {
  std::vector<Format> out;
  for (const auto& n : builtinFormatNames()) out.push_back(parseFormat(n));
  out.push_back(parseFormat("rgba:e8m7"));
  out.push_back(parseFormat("rgba:e5m2"));
  out.push_back(parseFormat("rg:e4m3fn"));
  return out;
}

}  // namespace

TEST_CASE("blend: every factor pair and equation on every format matches the table reference", "[blend]") {
  test::BitStream rng(2024);
  const std::vector<Format> formats = allFormats();
  size_t cases = 0;
  for (const Format& f : formats) {
    for (int eq = 0; eq < 5; ++eq)
      for (int sf = 0; sf < 15; ++sf)
        for (int df = 0; df < 15; ++df)
          for (int k = 0; k < 3; ++k) {
            BlendState st = BlendState::separate(BlendEquation(eq), BlendEquation((eq + k) % 5), BlendFactor(sf),
                                                 BlendFactor(df), BlendFactor((sf + 3 * k) % 15), BlendFactor((df + 5 * k) % 15));
            glm::vec4 src, dstIn, constant;
            for (int i = 0; i < 4; ++i) {
              src[i] = rng.uniform(-0.5f, 2.0f);
              dstIn[i] = rng.uniform(-0.5f, 2.0f);
              constant[i] = rng.uniform(-0.5f, 2.0f);
            }
            uint8_t texel[16];
            encodeTexel(f, dstIn, exactProfile(), texel);
            const glm::vec4 dst = decodeTexel(f, texel);
            const glm::vec4 want = referenceBlend(st, src, dst, constant, f);
            blendIntoTexel(f, st, constant, exactProfile(), src, texel);
            for (int c = 0; c < f.channels; ++c) {
              const int64_t e = expectedChannelBits(f, c, want[c]);
              const uint32_t got = storedChannelBits(f, texel, c);
              if (e == -1 ? !std::isnan(decodeTexel(f, texel)[c]) : got != uint32_t(e))
                FAIL(f.name() << " " << st.describe() << " channel " << c << " src " << src[c] << " dst " << dst[c]
                              << " const " << constant[c] << ": reference " << want[c] << " -> " << std::hex << e
                              << ", stored " << got);
            }
            ++cases;
          }
  }
  CHECK(cases == formats.size() * 5 * 15 * 15 * 3);
}

TEST_CASE("blend: hand-derived edge cases", "[blend]") {
  auto run = [](const char* format, BlendState st, glm::vec4 dst, glm::vec4 src, glm::vec4 constant = glm::vec4(0),
                const Profile& p = exactProfile()) {
    const Format f = parseFormat(format);
    uint8_t t[16];
    encodeTexel(f, dst, p, t);
    blendIntoTexel(f, st, constant, p, src, t);
    return texelBitsToString(f, t);
  };
  const BlendState over = BlendState::separate(BlendEquation::Add, BlendEquation::Add, BlendFactor::SrcAlpha,
                                               BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::OneMinusSrcAlpha);
  const BlendState add = BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::One);
  const BlendState replace = BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::Zero);

  // OVER of (1,0,0,.5) on (0,0,1,1): R = .5 -> 127.5 -> 128; B = .5 -> 128; A = .5 + .5 = 1.
  CHECK(run("rgba8", over, {0, 0, 1, 1}, {1, 0, 0, 0.5f}) == "80 00 80 ff");
  // llvmpipe: A8 = 128 (127.5 ties to even); B = 255·(255−128)/255 = mul(255,127) = 127.
  CHECK(run("rgba8", over, {0, 0, 1, 1}, {1, 0, 0, 0.5f}, glm::vec4(0), llvmpipeProfile()) == "80 00 7f ff");
  // fp16 accumulation overflows to inf past 65504 (round to nearest); toward zero stays at 65504.
  CHECK(run("rgba16f", add, {60000, 0, 0, 0}, {6000, 0, 0, 0}) == "7c00 0000 0000 0000");
  CHECK(run("rgba16f", add, {60000, 0, 0, 0}, {6000, 0, 0, 0}, glm::vec4(0), llvmpipeProfile()) == "7bff 0000 0000 0000");
  // Fixed point clamps the source and the constant; float targets do not.
  CHECK(run("rgba8", replace, {0, 0, 0, 0}, {2, -1, 0.5f, 7}) == "ff 00 80 ff");
  CHECK(run("rgba16f", replace, {0, 0, 0, 0}, {2, -1, 0.5f, 7}) == "4000 bc00 3800 4700");
  const BlendState constant = BlendState::same(BlendEquation::Add, BlendFactor::ConstantColor, BlendFactor::Zero);
  CHECK(run("rgba8", constant, {0, 0, 0, 0}, {0.5f, 0.5f, 0.5f, 0.5f}, {2, -1, 0.5f, 1}) == "80 00 40 80");
  CHECK(run("rgba16f", constant, {0, 0, 0, 0}, {0.5f, 0.5f, 0.5f, 0.5f}, {2, -1, 0.5f, 1}) == "3c00 b800 3400 3800");
  // NaN: UNORM stores 0; fp16 keeps a quiet NaN; 0·inf is NaN (IEEE, as written).
  CHECK(run("rgba8", replace, {1, 1, 1, 1}, {NAN, 1, 1, 1}) == "00 ff ff ff");
  CHECK(run("rgba16f", replace, {1, 1, 1, 1}, {NAN, 1, 1, 1}) == "7e00 3c00 3c00 3c00");
  CHECK(run("rgba16f", replace, {INFINITY, 1, 1, 1}, {1, 1, 1, 1}) == "7e00 3c00 3c00 3c00");
  // MIN/MAX ignore the factors.
  const BlendState minZero = BlendState::same(BlendEquation::Min, BlendFactor::Zero, BlendFactor::Zero);
  const BlendState maxZero = BlendState::same(BlendEquation::Max, BlendFactor::Zero, BlendFactor::Zero);
  CHECK(run("rgba16f", minZero, {0.5f, 2, -3, 1}, {1, 1, 1, 1}) == "3800 3c00 c200 3c00");
  CHECK(run("rgba16f", maxZero, {0.5f, 2, -3, 1}, {1, 1, 1, 1}) == "3c00 4000 3c00 3c00");
  CHECK(run("rgba16f", minZero, {0.5f, 0.5f, 0.5f, 0.5f}, {NAN, 1, 1, 1}) == "3800 3800 3800 3800");
  // SRC_ALPHA_SATURATE: RGB factor min(As = .5, 1 − Ad = .25) = .25; alpha factor 1.
  const BlendState saturate = BlendState::same(BlendEquation::Add, BlendFactor::SrcAlphaSaturate, BlendFactor::Zero);
  CHECK(run("rgba16f", saturate, {0, 0, 0, 0.75f}, {1, 2, 4, 0.5f}) == "3400 3800 3c00 3800");
  // A target without alpha reads Ad = 1: one_minus_dst_alpha is 0, saturate is min(As, 0) = 0.
  const BlendState oneMinusDstAlpha = BlendState::same(BlendEquation::Add, BlendFactor::OneMinusDstAlpha, BlendFactor::One);
  CHECK(run("r16f", oneMinusDstAlpha, {0.25f, 0, 0, 0}, {1, 0, 0, 0}) == "3400");
  CHECK(run("rg8", saturate, {0, 0, 0, 0}, {1, 1, 0, 1}) == "00 00");
  // R11G11B10F: negative results store 0, finite overflow stores the largest finite value.
  const BlendState revsub = BlendState::same(BlendEquation::ReverseSubtract, BlendFactor::One, BlendFactor::One);
  CHECK(run("r11g11b10f", revsub, {1, 1, 1, 0}, {2, 0.5f, 1, 0}) == "001c0000");  // 0, 0.5, 0
  CHECK(run("r11g11b10f", add, {65024, 0, 0, 0}, {65024, 0, 0, 0}) == "000007bf");
  // Write mask: only G and A change.
  BlendState masked = replace;
  masked.writeMask = 0b1010;
  CHECK(run("rgba8", masked, {0, 0, 0, 0}, {1, 1, 1, 1}) == "00 ff 00 ff");
  CHECK(run("rgb10a2", masked, {0, 0, 0, 0}, {1, 1, 1, 1}) == "c00ffc00");
  // Blending disabled: the source converted, write mask still applies.
  BlendState off;
  off.writeMask = 0b0001;
  CHECK(run("rgba16f", off, {1, 1, 1, 1}, {0.5f, 0.5f, 0.5f, 0.5f}) == "3800 3c00 3c00 3c00");
}

TEST_CASE("blend: llvmpipe's a·b/255 is exact rounding except on the 24 products just above k + 0.5", "[blend]") {
  // Measured with `oitref glcheck blend` on all 65536 pairs (docs/rules.md); here the formula is
  // checked against exact rounding: it rounds down exactly the quotients k + 0.502.
  int roundedDown = 0;
  for (uint32_t a = 0; a < 256; ++a)
    for (uint32_t b = 0; b < 256; ++b) {
      const double q = double(a * b) / 255.0;
      const uint32_t exact = uint32_t(std::floor(q + 0.5));
      if (detail::mulUnorm8(a, b) == exact) continue;
      ++roundedDown;
      REQUIRE(detail::mulUnorm8(a, b) + 1 == exact);
      REQUIRE(q - std::floor(q) > 0.5);
      REQUIRE(q - std::floor(q) < 0.503);
    }
  CHECK(roundedDown == 24);
  CHECK(detail::mulUnorm8(244, 197) == 188);  // 188.502
}

TEST_CASE("blend: llvmpipe integer path follows its rules on random cases", "[blend]") {
  // Reference: quantise source and constant by the fp32-product rule, then integer arithmetic.
  test::BitStream rng(8);
  const Format f = makeFormat(FormatId::RGBA8);
  const Profile p = llvmpipeProfile();
  auto q = [](float v) { return uint32_t(std::nearbyint(clampUnit(v) * 255.0f)); };
  for (int i = 0; i < 20000; ++i) {
    const BlendState st = BlendState::separate(BlendEquation(i % 5), BlendEquation((i / 5) % 5), BlendFactor(i % 15),
                                               BlendFactor((i / 15) % 15), BlendFactor((i / 7) % 15), BlendFactor((i / 11) % 15));
    glm::vec4 s, c;
    uint8_t t[4];
    for (int k = 0; k < 4; ++k) {
      s[k] = rng.uniform(-0.2f, 1.2f);
      c[k] = rng.uniform(-0.2f, 1.2f);
      t[k] = uint8_t(rng.next() & 0xff);
    }
    uint32_t S[4], D[4], C[4];
    for (int k = 0; k < 4; ++k) S[k] = q(s[k]), D[k] = t[k], C[k] = q(c[k]);
    auto fac = [&](BlendFactor bf, int k) -> uint32_t {
      switch (bf) {
        case BlendFactor::Zero: return 0;
        case BlendFactor::One: return 255;
        case BlendFactor::SrcColor: return S[k];
        case BlendFactor::OneMinusSrcColor: return 255 - S[k];
        case BlendFactor::DstColor: return D[k];
        case BlendFactor::OneMinusDstColor: return 255 - D[k];
        case BlendFactor::SrcAlpha: return S[3];
        case BlendFactor::OneMinusSrcAlpha: return 255 - S[3];
        case BlendFactor::DstAlpha: return D[3];
        case BlendFactor::OneMinusDstAlpha: return 255 - D[3];
        case BlendFactor::ConstantColor: return C[k];
        case BlendFactor::OneMinusConstantColor: return 255 - C[k];
        case BlendFactor::ConstantAlpha: return C[3];
        case BlendFactor::OneMinusConstantAlpha: return 255 - C[3];
        case BlendFactor::SrcAlphaSaturate: return k == 3 ? 255 : std::min(S[3], 255 - D[3]);
      }
      return 0;
    };
    uint32_t want[4];
    for (int k = 0; k < 4; ++k) {
      const BlendEquation e = k == 3 ? st.equationAlpha : st.equationRgb;
      // lp_build_mul_norm as documented: (ab + ab/256 + 128) / 256 in integers.
      auto mul = [](uint32_t x, uint32_t y) { return int((x * y + x * y / 256 + 128) / 256); };
      const int a = mul(S[k], fac(k == 3 ? st.srcAlpha : st.srcRgb, k));
      const int b = mul(D[k], fac(k == 3 ? st.dstAlpha : st.dstRgb, k));
      const int r = e == BlendEquation::Add ? a + b : e == BlendEquation::Subtract ? a - b
                  : e == BlendEquation::ReverseSubtract ? b - a : e == BlendEquation::Min ? int(std::min(S[k], D[k]))
                                                                                           : int(std::max(S[k], D[k]));
      want[k] = uint32_t(std::clamp(r, 0, 255));
    }
    blendIntoTexel(f, st, c, p, s, t);
    for (int k = 0; k < 4; ++k) REQUIRE(t[k] == want[k]);
  }
}

TEST_CASE("blend: state prints and parses", "[blend]") {
  const BlendState st = BlendState::separate(BlendEquation::Add, BlendEquation::Max, BlendFactor::SrcAlpha,
                                             BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::Zero);
  CHECK(st.describe() == "add,max src_alpha,one_minus_src_alpha,one,zero mask=rgba");
  CHECK(BlendState{}.describe() == "blend off mask=rgba");
  for (int i = 0; i < 15; ++i) CHECK(parseBlendFactor(toString(BlendFactor(i))) == BlendFactor(i));
  for (int i = 0; i < 5; ++i) CHECK(parseBlendEquation(toString(BlendEquation(i))) == BlendEquation(i));
  CHECK_THROWS_WITH(parseBlendFactor("src_alpa"), Catch::Contains("src_alpha"));
}

TEST_CASE("blend: fast paths give the generic path's bits", "[blend]") {
  // Random destination bit patterns (NaN, inf and denormals included for float formats), random
  // sources including specials, every equation and factor, blending on and off, both profiles.
  test::BitStream rng(99);
  const float specials[] = {NAN, -NAN, INFINITY, -INFINITY, 0.0f, -0.0f, 1e-40f, 65520.0f, 1.0f, 0.5f};
  int compared = 0;
  for (const char* name : {"rgba8", "rg8", "r8", "rgba16f", "rg16f", "r16f", "rgba32f", "rg32f", "r32f"}) {
    const Format f = parseFormat(name);
    for (const Profile& p : {exactProfile(), llvmpipeProfile(), parseProfile("llvmpipe,unorm_blend=float"), nvidiaProfile()})
      for (int i = 0; i < 6000; ++i) {
        BlendState st = BlendState::separate(BlendEquation(i % 5), BlendEquation((i / 5) % 5), BlendFactor(rng.next() % 15),
                                             BlendFactor(rng.next() % 15), BlendFactor(rng.next() % 15),
                                             BlendFactor(rng.next() % 15));
        st.enabled = i % 7 != 0;
        glm::vec4 src, constant;
        for (int k = 0; k < 4; ++k) {
          src[k] = rng.next() % 5 == 0 ? specials[rng.next() % 10] : rng.uniform(-1.0f, 3.0f);
          constant[k] = rng.uniform(-0.5f, 1.5f);
        }
        uint8_t fast[16], generic[16];
        for (int b = 0; b < 16; ++b) fast[b] = uint8_t(rng.next());
        std::memcpy(generic, fast, 16);
        detail::TargetBlender(f, st, constant, p, true).blend(src, fast);
        detail::TargetBlender(f, st, constant, p, false).blend(src, generic);
        if (std::memcmp(fast, generic, size_t(f.bytesPerTexel())) != 0)
          FAIL(name << " " << p.describe() << " " << st.describe() << ": fast " << texelBitsToString(f, fast)
                    << ", generic " << texelBitsToString(f, generic));
        ++compared;
      }
  }
  CHECK(compared == 9 * 4 * 6000);
}
