// Render-target colour formats, stored in their real bit layout.
//
// A texel is the format's own bytes: rgba16f is 4 little-endian binary16 halves (8 bytes),
// r11g11b10f one 32-bit word laid out as GL's UNSIGNED_INT_10F_11F_11F_REV (R bits 0–10,
// G 11–21, B 22–31), rgb10a2 one word as UNSIGNED_INT_2_10_10_10_REV (R 0–9, G 10–19, B 20–29,
// A 30–31). A user minifloat format ("rgba:e8m7") stores each channel in the smallest of 1, 2
// or 4 bytes that holds its bits.
//
// Reading a texel gives (r, g, b, a) with missing channels as GL fills them: G = B = 0, A = 1
// (GL 4.6 §15.2.1, table 15.1).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "oitref/core/minifloat.h"
#include "oitref/core/profile.h"

namespace oitref {

enum class FormatId : uint8_t {
  R8, RG8, RGBA8, RGB10A2,
  R16, RG16, RGBA16,  // 16-bit UNORM
  R16F, RG16F, RGBA16F,
  R32F, RG32F, RGBA32F,
  R11G11B10F,
  Minifloat,  // user-defined: channels × MinifloatSpec
};

enum class ChannelEncoding : uint8_t { Unorm, Half, Float32, PackedFloat11_10, Minifloat };

struct Format {
  FormatId id = FormatId::RGBA8;
  int channels = 4;
  MinifloatSpec minifloat{};  // meaningful for FormatId::Minifloat only

  bool operator==(const Format& o) const;
  std::string name() const;  // "rgba16f", "rgba:e8m7", ...
  ChannelEncoding encoding() const;
  int bytesPerTexel() const;
  int bytesPerChannel() const;  // 0 for packed formats (one word holds all channels)
  bool isPacked() const { return id == FormatId::RGB10A2 || id == FormatId::R11G11B10F; }
  bool isUnorm() const { return encoding() == ChannelEncoding::Unorm; }
  bool hasAlpha() const { return channels == 4; }
  int unormBits(int channel) const;  // rgba8: 8; rgba16: 16; rgb10a2: 10,10,10,2
};

Format makeFormat(FormatId id);
Format makeMinifloatFormat(int channels, const MinifloatSpec& spec);
// Accepts the names above plus "<r|rg|rgb|rgba>:<minifloat spec>". Throws std::invalid_argument
// listing the valid names.
Format parseFormat(const std::string& name);
std::vector<std::string> builtinFormatNames();

// fp32 RGBA -> the texel's bytes, each channel converted by its rule under the profile.
// Only the first `channels` components are used.
void encodeTexel(const Format& format, const glm::vec4& value, const Profile& profile, uint8_t* texel);
// The texel's bytes -> exact fp32 values, missing channels filled as GL does.
glm::vec4 decodeTexel(const Format& format, const uint8_t* texel);
// decodeTexel for one format, chosen once (Image::fetch): a function compiled for the layout
// when the format is r/rg/rgba in 8- or 16-bit UNORM, fp16 or fp32, else decodeTexel itself.
// Same bits either way.
using TexelDecoder = glm::vec4 (*)(const Format& format, const uint8_t* texel);
TexelDecoder texelDecoder(const Format& format);
// The texels at row + xs[i]·texelBytes for i < n (at row + i·texelBytes where xs is null: a run)
// decoded into out, as texelDecoder's function decodes each: one call per row, the decoding
// inlined into its loop.
using TexelRowDecoder = void (*)(const Format& format, const uint8_t* row, size_t texelBytes, const int* xs, int n,
                                 glm::vec4* out);
TexelRowDecoder texelRowDecoder(const Format& format);
// Copies channel c of `from` into `to` when bit c of mask is set (write masks on packed formats).
void mergeTexelChannels(const Format& format, const uint8_t* from, uint8_t* to, unsigned mask);
// The texel's bits as text: per channel in hex separated by spaces ("3c00 3800 0000 3c00"), one
// 32-bit hex word for packed formats.
std::string texelBitsToString(const Format& format, const uint8_t* texel);

}  // namespace oitref
