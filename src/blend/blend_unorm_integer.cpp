#include "blend/blend_unorm_integer.h"

#include <cstring>

#include "blend/blend_factor.h"
#include "blend/llvmpipe_factors.h"
#include "format/packed_layout.h"

namespace oitref::detail {
namespace {

// Channel ch of a factor: candidate row of blend_factor.h in w-bit integers, 1 − v as max − v.
uint32_t factorInteger(BlendFactor f, int ch, const uint32_t s[4], const uint32_t d[4], uint32_t ad, const uint32_t c[4],
                       uint32_t max) {
  const FactorRow fr = factorRow(f);
  uint32_t v = 0;
  switch (fr.row) {
    case 0: v = 0; break;
    case 1: v = s[ch]; break;
    case 2: v = ch == 3 ? ad : d[ch]; break;
    case 3: v = s[3]; break;
    case 4: v = ad; break;
    case 5: v = c[ch]; break;
    case 6: v = c[3]; break;
    case 7: v = ch == 3 ? max : (s[3] < max - ad ? s[3] : max - ad); break;
  }
  return fr.oneMinus ? max - v : v;
}

uint32_t equationInteger(BlendEquation eq, uint32_t s, uint32_t d, uint32_t sf, uint32_t df, int w) {
  const int64_t a = mulUnormInteger(s, sf, w), b = mulUnormInteger(d, df, w), max = (int64_t(1) << w) - 1;
  int64_t r = 0;
  switch (eq) {
    case BlendEquation::Add: r = a + b; break;
    case BlendEquation::Subtract: r = a - b; break;
    case BlendEquation::ReverseSubtract: r = b - a; break;
    case BlendEquation::Min: return s < d ? s : d;
    case BlendEquation::Max: return s > d ? s : d;
  }
  return uint32_t(r < 0 ? 0 : r > max ? max : r);  // saturating, as the integer ops are
}

// lp_build_lerp on 8-bit normalized integers (SSSE3 pmulhrsw path): x scaled to [0, 256] as
// x + (x >> 7), then v0 + ((x·(v1 − v0) + 128) >> 8) (arithmetic shift), modulo 256.
uint32_t lerpUnorm8(uint32_t x, uint32_t v0, uint32_t v1) {
  const int scaled = int(x + (x >> 7));
  const int delta = int(v1) - int(v0);
  const int step = (scaled * delta + 128) >> 8;  // C++20: >> on negatives is arithmetic
  return uint32_t(int(v0) + step) & 0xffu;
}

// The same on 16-bit normalized integers, widened to 32 bits (no pmulhrsw): x scaled to
// [0, 65536] as x + (x >> 15), then v0 + ((x·(v1 − v0)) >> 16), truncating (arithmetic shift).
uint32_t lerpUnorm16(uint32_t x, uint32_t v0, uint32_t v1) {
  const int64_t scaled = int64_t(x + (x >> 15));
  const int64_t delta = int64_t(v1) - int64_t(v0);
  return uint32_t(int64_t(v0) + ((scaled * delta) >> 16)) & 0xffffu;
}

// llvmpipe blends a one-channel UNORM target with complementary factors and ADD as a lerp
// (lp_build_blend: the factors cannot differ between channels when there is one channel).
// Factors are first sanitised as llvmpipe does for targets without alpha.
bool isLerpCase(const Format& f, const BlendState& st, unsigned& fs, unsigned& fd) {
  if (f.channels != 1 || st.equationRgb != BlendEquation::Add) return false;
  auto sanitise = [](unsigned p) {
    return p == kPipeDstAlpha ? kPipeOne : (p == kPipeInvDstAlpha || p == kPipeSrcAlphaSaturate) ? kPipeZero : p;
  };
  fs = sanitise(pipeFactor(st.srcRgb));
  fd = sanitise(pipeFactor(st.dstRgb));
  return pipeComplementary(fs, fd);
}

int channelBits(const Format& f, int ch) { return f.unormBits(ch); }

// The stored n-bit codes of the texel (missing channels: 0, alpha max).
void loadCodes(const Format& f, const uint8_t* texel, uint32_t codes[4]) {
  if (f.id == FormatId::RGB10A2) {
    uint32_t w;
    std::memcpy(&w, texel, 4);
    for (int ch = 0; ch < 4; ++ch) codes[ch] = (w >> kRgb10a2Shift[ch]) & ((1u << kRgb10a2Bits[ch]) - 1);
  } else {
    const int bytes = f.unormBits(0) / 8;
    for (int ch = 0; ch < f.channels; ++ch) {
      codes[ch] = 0;
      std::memcpy(&codes[ch], texel + ch * bytes, size_t(bytes));  // little-endian, like the texel
    }
  }
}

void storeCodes(const Format& f, const uint32_t codes[4], unsigned mask, uint8_t* texel) {
  if (f.id == FormatId::RGB10A2) {
    uint32_t w;
    std::memcpy(&w, texel, 4);
    for (int ch = 0; ch < 4; ++ch) {
      if (!(mask & (1u << ch))) continue;
      const uint32_t m = ((1u << kRgb10a2Bits[ch]) - 1) << kRgb10a2Shift[ch];
      w = (w & ~m) | (codes[ch] << kRgb10a2Shift[ch]);
    }
    std::memcpy(texel, &w, 4);
  } else {
    const int bytes = f.unormBits(0) / 8;
    for (int ch = 0; ch < f.channels; ++ch)
      if (mask & (1u << ch)) std::memcpy(texel + ch * bytes, &codes[ch], size_t(bytes));
  }
}

}  // namespace

void blendUnormInteger(const Format& f, const BlendState& state, const glm::vec4& constant, UnormRounding rounding,
                       const glm::vec4& source, unsigned writeMask, uint8_t* texel) {
  const int w = unormBlendWidth(f);
  const uint32_t max = (1u << w) - 1;
  uint32_t s[4], d[4] = {0, 0, 0, max}, c[4], codes[4] = {0, 0, 0, 0};
  for (int ch = 0; ch < 4; ++ch) {
    s[ch] = encodeUnorm(source[ch], w, rounding);
    c[ch] = encodeUnorm(constant[ch], w, rounding);
  }
  loadCodes(f, texel, codes);
  for (int ch = 0; ch < f.channels; ++ch) d[ch] = widenUnormBits(codes[ch], channelBits(f, ch), w);
  const uint32_t ad = f.hasAlpha() ? d[3] : max;
  unsigned fs = 0, fd = 0;
  if ((w == 8 || f.unormBits(0) == 16) && isLerpCase(f, state, fs, fd)) {
    auto lerp = w == 8 ? lerpUnorm8 : lerpUnorm16;
    if (writeMask & 1u) {
      const uint32_t sf = factorInteger(state.srcRgb, 0, s, d, ad, c, max), df = factorInteger(state.dstRgb, 0, s, d, ad, c, max);
      codes[0] = fs < fd ? lerp(sf, d[0], s[0]) : lerp(df, s[0], d[0]);
    }
    storeCodes(f, codes, writeMask, texel);
    return;
  }
  for (int ch = 0; ch < f.channels; ++ch) {
    if (!(writeMask & (1u << ch))) continue;
    const bool alpha = ch == 3;
    const uint32_t sf = factorInteger(alpha ? state.srcAlpha : state.srcRgb, ch, s, d, ad, c, max);
    const uint32_t df = factorInteger(alpha ? state.dstAlpha : state.dstRgb, ch, s, d, ad, c, max);
    const uint32_t r = equationInteger(alpha ? state.equationAlpha : state.equationRgb, s[ch], d[ch], sf, df, w);
    codes[ch] = narrowUnormBits(r, w, channelBits(f, ch));
  }
  storeCodes(f, codes, writeMask, texel);
}

}  // namespace oitref::detail
