// Format descriptors and texel packing. Per-channel rules live in unorm.cpp, minifloat.cpp and
// fp16.cpp; this file only decides which rule applies where, and where the bits go.
#include "oitref/core/format.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "format/fp16_inline.h"
#include "format/packed_layout.h"
#include "format/unorm8_decode.h"
#include "format/unorm_rescale.h"
#include "oitref/core/unorm.h"

namespace oitref {
namespace {

struct BuiltinFormat {
  const char* name;
  FormatId id;
  int channels;
};
constexpr BuiltinFormat kBuiltins[] = {
    {"r8", FormatId::R8, 1},         {"rg8", FormatId::RG8, 2},         {"rgba8", FormatId::RGBA8, 4},
    {"r16", FormatId::R16, 1},       {"rg16", FormatId::RG16, 2},       {"rgba16", FormatId::RGBA16, 4},
    {"rgb10a2", FormatId::RGB10A2, 4}, {"r16f", FormatId::R16F, 1},     {"rg16f", FormatId::RG16F, 2},
    {"rgba16f", FormatId::RGBA16F, 4}, {"r32f", FormatId::R32F, 1},     {"rg32f", FormatId::RG32F, 2},
    {"rgba32f", FormatId::RGBA32F, 4}, {"r11g11b10f", FormatId::R11G11B10F, 3},
};

using detail::kF11F10Shift;
using detail::kRgb10a2Bits;
using detail::kRgb10a2Shift;

uint32_t loadWord(const uint8_t* p) {
  uint32_t w;
  std::memcpy(&w, p, 4);
  return w;
}
void storeWord(uint8_t* p, uint32_t w) { std::memcpy(p, &w, 4); }

uint32_t loadChannel(const uint8_t* texel, int c, int bytes) {
  uint32_t v = 0;
  std::memcpy(&v, texel + c * bytes, bytes);
  return v;
}
void storeChannel(uint8_t* texel, int c, int bytes, uint32_t v) { std::memcpy(texel + c * bytes, &v, bytes); }

const MinifloatSpec& packedSpec(int channel) { return channel < 2 ? kFloat11Spec : kFloat10Spec; }

}  // namespace

bool Format::operator==(const Format& o) const {
  return id == o.id && channels == o.channels && (id != FormatId::Minifloat || minifloat == o.minifloat);
}

std::string Format::name() const {
  if (id == FormatId::Minifloat) {
    static const char* prefixes[] = {"", "r", "rg", "rgb", "rgba"};
    return std::string(prefixes[channels]) + ":" + minifloat.name();
  }
  for (const auto& b : kBuiltins)
    if (b.id == id) return b.name;
  return "?";
}

ChannelEncoding Format::encoding() const {
  switch (id) {
    case FormatId::R8: case FormatId::RG8: case FormatId::RGBA8: case FormatId::RGB10A2:
    case FormatId::R16: case FormatId::RG16: case FormatId::RGBA16:
      return ChannelEncoding::Unorm;
    case FormatId::R16F: case FormatId::RG16F: case FormatId::RGBA16F: return ChannelEncoding::Half;
    case FormatId::R32F: case FormatId::RG32F: case FormatId::RGBA32F: return ChannelEncoding::Float32;
    case FormatId::R11G11B10F: return ChannelEncoding::PackedFloat11_10;
    case FormatId::Minifloat: return ChannelEncoding::Minifloat;
  }
  return ChannelEncoding::Unorm;
}

int Format::bytesPerChannel() const {
  switch (encoding()) {
    case ChannelEncoding::Unorm: return id == FormatId::RGB10A2 ? 0 : unormBits(0) / 8;
    case ChannelEncoding::Half: return 2;
    case ChannelEncoding::Float32: return 4;
    case ChannelEncoding::PackedFloat11_10: return 0;
    case ChannelEncoding::Minifloat: {
      const int bits = minifloat.totalBits();
      return bits <= 8 ? 1 : bits <= 16 ? 2 : 4;
    }
  }
  return 0;
}

int Format::bytesPerTexel() const { return isPacked() ? 4 : channels * bytesPerChannel(); }

int Format::unormBits(int channel) const {
  if (id == FormatId::RGB10A2) return kRgb10a2Bits[channel];
  return id == FormatId::R16 || id == FormatId::RG16 || id == FormatId::RGBA16 ? 16 : 8;
}

Format makeFormat(FormatId id) {
  for (const auto& b : kBuiltins)
    if (b.id == id) return Format{b.id, b.channels, {}};
  throw std::invalid_argument("makeFormat: use makeMinifloatFormat for minifloat formats");
}

Format makeMinifloatFormat(int channels, const MinifloatSpec& spec) {
  if (channels < 1 || channels > 4) throw std::invalid_argument("minifloat format needs 1..4 channels");
  spec.validate();
  return Format{FormatId::Minifloat, channels, spec};
}

std::vector<std::string> builtinFormatNames() {
  std::vector<std::string> names;
  for (const auto& b : kBuiltins) names.push_back(b.name);
  return names;
}

Format parseFormat(const std::string& name) {
  for (const auto& b : kBuiltins)
    if (name == b.name) return Format{b.id, b.channels, {}};
  const auto colon = name.find(':');
  if (colon != std::string::npos) {
    const std::string ch = name.substr(0, colon);
    const int channels = ch == "r" ? 1 : ch == "rg" ? 2 : ch == "rgb" ? 3 : ch == "rgba" ? 4 : 0;
    if (channels == 0)
      throw std::invalid_argument("format '" + name + "': channel prefix must be r, rg, rgb or rgba");
    return makeMinifloatFormat(channels, parseMinifloatSpec(name.substr(colon + 1)));
  }
  std::string valid;
  for (const auto& n : builtinFormatNames()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown format '" + name + "' (valid: " + valid +
                              ", or <r|rg|rgb|rgba>:e<E>m<M>… for a minifloat, e.g. rgba:e8m7)");
}

void encodeTexel(const Format& f, const glm::vec4& v, const Profile& profile, uint8_t* texel) {
  switch (f.encoding()) {
    case ChannelEncoding::Unorm:
      if (f.id == FormatId::RGB10A2) {
        uint32_t w = 0;
        for (int c = 0; c < 4; ++c) {
          // llvmpipe writes these channels through its 16-bit blend integers even with blending off.
          const uint32_t code =
              profile.unormBlend == UnormBlend::Integer ? detail::encodeUnormThroughWidth(v[c], kRgb10a2Bits[c], 16, profile.unorm)
              : profile.unorm == UnormRounding::NvidiaFixed && c == 3 ? detail::nvidiaAlpha2From10(encodeUnorm(v[c], 10, profile.unorm))
                                                                      : encodeUnorm(v[c], kRgb10a2Bits[c], profile.unorm);
          w |= code << kRgb10a2Shift[c];
        }
        storeWord(texel, w);
      } else {
        const int bits = f.unormBits(0);
        for (int c = 0; c < f.channels; ++c) storeChannel(texel, c, bits / 8, encodeUnorm(v[c], bits, profile.unorm));
      }
      return;
    case ChannelEncoding::Half:
      for (int c = 0; c < f.channels; ++c) storeChannel(texel, c, 2, detail::encodeHalfInline(v[c], profile.fp16));
      return;
    case ChannelEncoding::Float32:
      std::memcpy(texel, &v[0], 4 * f.channels);  // fp32 -> fp32: the bits as they are
      return;
    case ChannelEncoding::PackedFloat11_10: {
      uint32_t w = 0;
      for (int c = 0; c < 3; ++c) w |= encodeMinifloat(v[c], packedSpec(c), profile.packedFloat) << kF11F10Shift[c];
      storeWord(texel, w);
      return;
    }
    case ChannelEncoding::Minifloat: {
      const int bytes = f.bytesPerChannel();
      for (int c = 0; c < f.channels; ++c)
        storeChannel(texel, c, bytes, encodeMinifloat(v[c], f.minifloat, profile.minifloat));
      return;
    }
  }
}

namespace {

// One channel of the unpacked encodings, by its rule (unorm.h, fp16_inline.h; fp32 as it is).
template <ChannelEncoding E, int Bytes>
float decodeChannel(const uint8_t* texel, int c) {
  if constexpr (E == ChannelEncoding::Unorm && Bytes == 1) return detail::kUnorm8Decode[texel[c]];
  else if constexpr (E == ChannelEncoding::Unorm) return decodeUnorm(loadChannel(texel, c, Bytes), 8 * Bytes);
  else if constexpr (E == ChannelEncoding::Half) return detail::decodeHalfInline(uint16_t(loadChannel(texel, c, 2)));
  else {
    float v;
    std::memcpy(&v, texel + 4 * c, 4);
    return v;
  }
}

template <ChannelEncoding E, int Bytes>
glm::vec4 decodeChannels(int channels, const uint8_t* texel) {
  glm::vec4 out(0.0f, 0.0f, 0.0f, 1.0f);
  for (int c = 0; c < channels; ++c) out[c] = decodeChannel<E, Bytes>(texel, c);
  return out;
}

template <ChannelEncoding E, int Bytes, int Channels>
glm::vec4 decodeFixedLayout(const Format&, const uint8_t* texel) {
  if constexpr (E == ChannelEncoding::Half && Channels == 4) {  // RGBA16F: the four halves at once
    glm::vec4 out;
    detail::decodeHalf4Inline(texel, &out.x);
    return out;
  }
  return decodeChannels<E, Bytes>(Channels, texel);
}

template <ChannelEncoding E, int Bytes, int Channels>
void decodeFixedLayoutRow(const Format&, const uint8_t* row, size_t texelBytes, const int* xs, int n, glm::vec4* out) {
  auto each = [&](auto decode) {
    if (xs)
      for (int i = 0; i < n; ++i) decode(row + size_t(xs[i]) * texelBytes, out[i]);
    else
      for (int i = 0; i < n; ++i) decode(row + size_t(i) * texelBytes, out[i]);
  };
  if constexpr (E == ChannelEncoding::Half && Channels == 4)  // RGBA16F: the four halves of a texel at once
    each([](const uint8_t* t, glm::vec4& v) { detail::decodeHalf4Inline(t, &v.x); });
  else
    each([](const uint8_t* t, glm::vec4& v) { v = decodeChannels<E, Bytes>(Channels, t); });
}
void decodeRow(const Format& f, const uint8_t* row, size_t texelBytes, const int* xs, int n, glm::vec4* out) {
  for (int i = 0; i < n; ++i) out[i] = decodeTexel(f, row + size_t(xs ? xs[i] : i) * texelBytes);
}

// The kernel for the format's layout: kernel.operator()<E, Bytes, Channels>() for the layouts
// with a fixed-layout kernel (8- and 16-bit UNORM, fp16, fp32; one, two or four channels), else
// `general`. One choice for texelDecoder and texelRowDecoder.
template <typename Fn, typename Kernel>
Fn fixedLayoutKernel(const Format& f, Fn general, Kernel kernel) {
  if (f.isPacked()) return general;
  auto byChannels = [&]<ChannelEncoding E, int Bytes>() -> Fn {
    switch (f.channels) {
      case 1: return kernel.template operator()<E, Bytes, 1>();
      case 2: return kernel.template operator()<E, Bytes, 2>();
      case 4: return kernel.template operator()<E, Bytes, 4>();
      default: return general;
    }
  };
  switch (f.encoding()) {
    case ChannelEncoding::Unorm:
      return f.unormBits(0) == 8 ? byChannels.template operator()<ChannelEncoding::Unorm, 1>()
             : f.unormBits(0) == 16 ? byChannels.template operator()<ChannelEncoding::Unorm, 2>()
                                    : general;
    case ChannelEncoding::Half: return byChannels.template operator()<ChannelEncoding::Half, 2>();
    case ChannelEncoding::Float32: return byChannels.template operator()<ChannelEncoding::Float32, 4>();
    default: return general;
  }
}

}  // namespace

TexelDecoder texelDecoder(const Format& f) {
  return fixedLayoutKernel<TexelDecoder>(
      f, decodeTexel, []<ChannelEncoding E, int Bytes, int Channels>() { return decodeFixedLayout<E, Bytes, Channels>; });
}

TexelRowDecoder texelRowDecoder(const Format& f) {
  return fixedLayoutKernel<TexelRowDecoder>(
      f, decodeRow, []<ChannelEncoding E, int Bytes, int Channels>() { return decodeFixedLayoutRow<E, Bytes, Channels>; });
}

glm::vec4 decodeTexel(const Format& f, const uint8_t* texel) {
  glm::vec4 out(0.0f, 0.0f, 0.0f, 1.0f);
  switch (f.encoding()) {
    case ChannelEncoding::Unorm:
      if (f.id == FormatId::RGB10A2) {
        const uint32_t w = loadWord(texel);
        for (int c = 0; c < 4; ++c)
          out[c] = decodeUnorm((w >> kRgb10a2Shift[c]) & ((1u << kRgb10a2Bits[c]) - 1), kRgb10a2Bits[c]);
      } else if (f.unormBits(0) == 8) {
        out = decodeChannels<ChannelEncoding::Unorm, 1>(f.channels, texel);
      } else {
        out = decodeChannels<ChannelEncoding::Unorm, 2>(f.channels, texel);
      }
      break;
    case ChannelEncoding::Half:
      out = decodeChannels<ChannelEncoding::Half, 2>(f.channels, texel);
      break;
    case ChannelEncoding::Float32:
      out = decodeChannels<ChannelEncoding::Float32, 4>(f.channels, texel);
      break;
    case ChannelEncoding::PackedFloat11_10: {
      const uint32_t w = loadWord(texel);
      out[0] = decodeMinifloat(w & 0x7ffu, kFloat11Spec);
      out[1] = decodeMinifloat((w >> 11) & 0x7ffu, kFloat11Spec);
      out[2] = decodeMinifloat((w >> 22) & 0x3ffu, kFloat10Spec);
      break;
    }
    case ChannelEncoding::Minifloat: {
      const int bytes = f.bytesPerChannel();
      for (int c = 0; c < f.channels; ++c) out[c] = decodeMinifloat(loadChannel(texel, c, bytes), f.minifloat);
      break;
    }
  }
  return out;
}

void mergeTexelChannels(const Format& f, const uint8_t* from, uint8_t* to, unsigned mask) {
  if (f.isPacked()) {
    uint32_t keep = 0;
    for (int c = 0; c < f.channels; ++c) {
      if (!(mask & (1u << c))) continue;
      const int shift = f.id == FormatId::RGB10A2 ? kRgb10a2Shift[c] : kF11F10Shift[c];
      const int bits = f.id == FormatId::RGB10A2 ? kRgb10a2Bits[c] : (c < 2 ? 11 : 10);
      keep |= ((bits == 32 ? 0u : (1u << bits)) - 1u) << shift;
    }
    storeWord(to, (loadWord(from) & keep) | (loadWord(to) & ~keep));
    return;
  }
  const int bytes = f.bytesPerChannel();
  for (int c = 0; c < f.channels; ++c)
    if (mask & (1u << c)) std::memcpy(to + c * bytes, from + c * bytes, bytes);
}

std::string texelBitsToString(const Format& f, const uint8_t* texel) {
  char buf[16];
  if (f.isPacked()) {
    std::snprintf(buf, sizeof buf, "%08x", loadWord(texel));
    return buf;
  }
  const int bytes = f.bytesPerChannel();
  std::string s;
  for (int c = 0; c < f.channels; ++c) {
    std::snprintf(buf, sizeof buf, "%0*x", bytes * 2, loadChannel(texel, c, bytes));
    if (c) s += ' ';
    s += buf;
  }
  return s;
}

}  // namespace oitref
