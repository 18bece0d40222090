#include "tools/blend_case_generator.h"

#include <bit>
#include <cmath>
#include <limits>

#include "oitref/core/minifloat.h"
#include "util/seeded_random.h"

namespace oitref::tools {
namespace {

using util::SeededRandom;

// The minifloat spec of channel c when the format stores small floats; nullptr otherwise.
const MinifloatSpec* smallFloatSpec(const Format& f, int c) {
  switch (f.encoding()) {
    case ChannelEncoding::Half: return &kHalfSpec;
    case ChannelEncoding::PackedFloat11_10: return c < 2 ? &kFloat11Spec : &kFloat10Spec;
    case ChannelEncoding::Minifloat: return &f.minifloat;
    default: return nullptr;
  }
}

// Values at the edges of fp16, F11/F10 and fp32 that every implementation must get right.
constexpr float kEdges[] = {
    0x1p-24f, 0x1p-25f, 0x1.8p-25f, 0x3p-26f, 0x1p-14f, 0x1.ff8p-15f, 0x1.ffcp-15f,  // fp16 denormal edges
    65504.0f, 65519.99609375f, 65520.0f, 65536.0f, 65024.0f, 65040.0f, 64512.0f, 64520.0f,  // maxima
    0x1p-15f, 0x1p-17f, 0x1.2p-20f,                                                     // F11/F10 denormals
    1e-30f, 0x1p-126f, 0x1p-140f, 1e30f, 3.4028235e38f,                                 // tiny, fp32 denormal, huge
    0.0f, -0.0f, 1.0f, 0.5f, -1.0f, 0x1.fffffep-1f, 0x1.000002p+0f};

// A value exactly halfway between two neighbours of channel c's format, or the float nearest
// such a tie (UNORM ties k + ½ of 2^b − 1 steps are not floats), or one float beside it.
float formatTie(SeededRandom& r, const Format& f, int c) {
  if (const MinifloatSpec* spec = smallFloatSpec(f, c)) {
    const uint32_t maxFiniteCode = encodeMinifloat(largestFiniteMinifloat(*spec), *spec, Rounding::NearestEven);
    const uint32_t code = r.below(std::min<uint32_t>(maxFiniteCode, 1u << 24));
    const float lo = decodeMinifloat(code, *spec), hi = decodeMinifloat(code + 1, *spec);
    const float mid = lo + (hi - lo) * 0.5f;  // exact: the format has far fewer bits than fp32
    return (spec->isSigned && (r.bits() & 1)) ? -mid : mid;
  }
  if (f.isUnorm()) {
    const uint32_t steps = (1u << f.unormBits(c)) - 1;
    const float tie = float((double(r.below(steps)) + 0.5) / double(steps));
    switch (r.below(4)) {
      case 0: return std::nextafter(tie, 0.0f);
      case 1: return std::nextafter(tie, 2.0f);
      default: return tie;
    }
  }
  // fp32 targets store the value itself: any finite float of moderate size will do.
  return std::bit_cast<float>((r.bits() & 0x80000000u) | ((100u + r.below(56)) << 23) | (r.bits() & 0x7fffffu));
}

float pickAnyValue(SeededRandom& r, const Format& f, int c, bool nonFinite) {
  switch (r.below(nonFinite ? 8 : 7)) {
    case 0: return float(r.unit());                                   // the common case
    case 1:
    case 2: return formatTie(r, f, c);
    case 3: return r.bits() & 1 ? -float(r.unit()) * 2.0f : 1.0f + float(r.unit()) * 3.0f;  // out of [0,1]
    case 4: {
      const float e = kEdges[r.below(std::size(kEdges))];
      return r.below(4) == 0 ? -e : e;
    }
    case 5: {  // any representable value of the format, exactly
      if (const MinifloatSpec* spec = smallFloatSpec(f, c)) return decodeMinifloat(r.below(1u << std::min(spec->totalBits(), 24)), *spec);
      if (f.isUnorm()) return float(double(r.below(1u << f.unormBits(c))) / double((1u << f.unormBits(c)) - 1));
      return std::bit_cast<float>(r.bits() & 0xbfffffffu);  // finite: exponent below 128
    }
    case 6: return std::ldexp(float(r.unit()), int(r.below(60)) - 40);  // tiny to huge
    default: {
      const float specials[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                                -std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::quiet_NaN()};
      return specials[r.below(4)];
    }
  }
}

// Without nonFinite, values are finite (a random small-float code may be NaN or inf: drawn again).
float pickValue(SeededRandom& r, const Format& f, int c, bool nonFinite) {
  for (;;) {
    const float v = pickAnyValue(r, f, c, nonFinite);
    if (nonFinite || std::isfinite(v)) return v;
  }
}

BlendEquation pickEquation(SeededRandom& r) {
  const uint32_t k = r.below(8);  // ADD half the time: it is what OIT uses
  return k < 4 ? BlendEquation::Add : BlendEquation(k - 3);
}

// The states OIT methods use (OVER, premultiplied OVER, additive, WBOIT's accumulation and
// revealage, MIN/MAX for depth ranges, complementary constant blends): a quarter of the groups.
BlendState commonState(SeededRandom& r) {
  using E = BlendEquation;
  using F = BlendFactor;
  const BlendState states[] = {
      BlendState::same(E::Add, F::SrcAlpha, F::OneMinusSrcAlpha),
      BlendState::separate(E::Add, E::Add, F::SrcAlpha, F::OneMinusSrcAlpha, F::One, F::OneMinusSrcAlpha),
      BlendState::same(E::Add, F::One, F::OneMinusSrcAlpha),
      BlendState::same(E::Add, F::One, F::One),
      BlendState::same(E::Add, F::Zero, F::OneMinusSrcColor),
      BlendState::same(E::Add, F::Zero, F::OneMinusSrcAlpha),
      BlendState::same(E::Add, F::OneMinusDstAlpha, F::One),
      BlendState::same(E::Max, F::One, F::One),
      BlendState::same(E::Min, F::One, F::One),
      BlendState::same(E::Add, F::ConstantColor, F::OneMinusConstantColor),
      BlendState::same(E::Add, F::DstColor, F::Zero),
  };
  return states[r.below(std::size(states))];
}

glm::vec4 pickVec4(SeededRandom& r, const Format& f, bool nonFinite) {
  glm::vec4 v;
  for (int c = 0; c < 4; ++c) v[c] = pickValue(r, f, c, nonFinite);
  return v;
}

}  // namespace

std::vector<Format> glSharedFormats() {
  std::vector<Format> formats;
  for (const std::string& name : builtinFormatNames()) formats.push_back(parseFormat(name));
  return formats;
}

std::vector<BlendCase> generateBlendCases(const BlendCaseGeneratorOptions& o) {
  const std::vector<Format> formats = o.formats.empty() ? glSharedFormats() : o.formats;
  SeededRandom r(o.seed);
  std::vector<BlendCase> cases;
  cases.reserve(o.count);
  const size_t groupSize = std::max<size_t>(o.groupSize, 1);
  for (size_t group = 0; cases.size() < o.count; ++group) {
    BlendCase proto;
    proto.format = formats[group % formats.size()];
    if (r.below(4) == 0) {
      proto.state = commonState(r);
    } else {
      proto.state.enabled = true;
      proto.state.equationRgb = pickEquation(r);
      proto.state.equationAlpha = r.below(2) ? proto.state.equationRgb : pickEquation(r);
      proto.state.srcRgb = BlendFactor(r.below(15));
      proto.state.dstRgb = BlendFactor(r.below(15));
      proto.state.srcAlpha = BlendFactor(r.below(15));
      proto.state.dstAlpha = BlendFactor(r.below(15));
    }
    proto.constant = pickVec4(r, proto.format, o.nonFinite);
    for (size_t i = 0; i < groupSize && cases.size() < o.count; ++i) {
      BlendCase c = proto;
      c.destination = pickVec4(r, c.format, o.nonFinite);
      c.source = pickVec4(r, c.format, o.nonFinite);
      cases.push_back(c);
    }
  }
  return cases;
}

}  // namespace oitref::tools
