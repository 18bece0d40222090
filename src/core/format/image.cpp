#include "oitref/core/image.h"

#include "oitref/core/fp_environment.h"
#include "format/unorm8_decode.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace oitref {

size_t imageBytes(const Format& format, int width, int height) {
  return size_t(width) * size_t(height) * size_t(format.bytesPerTexel());
}

Image::Image(Format format, int width, int height) : format_(format), width_(width), height_(height) {
  if (width < 1 || height < 1 || width > kMaxDimension || height > kMaxDimension)
    throw std::invalid_argument("image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " outside 1.." + std::to_string(kMaxDimension));
  texelBytes_ = size_t(format.bytesPerTexel());
  decoder_ = texelDecoder(format);
  rowDecoder_ = texelRowDecoder(format);
  switch (format.id) {
    case FormatId::RGBA32F: inlineLayout_ = InlineLayout::Float32x4; break;
    case FormatId::RG32F: inlineLayout_ = InlineLayout::Float32x2; break;
    case FormatId::R32F: inlineLayout_ = InlineLayout::Float32x1; break;
    case FormatId::RGBA8: inlineLayout_ = InlineLayout::Unorm8x4; break;
    case FormatId::RG8: inlineLayout_ = InlineLayout::Unorm8x2; break;
    case FormatId::R8: inlineLayout_ = InlineLayout::Unorm8x1; break;
    default: break;
  }
  unorm8_ = detail::kUnorm8Decode.data();
  bytes_.assign(imageBytes(format, width, height), 0);
}

void Image::decodeFetchesAs(TextureFiltering rule) {
  exactUnorm8_ = rule != TextureFiltering::Llvmpipe;
  unorm8_ = exactUnorm8_ ? detail::kUnorm8Decode.data() : detail::kUnorm8DecodeLlvmpipe.data();
}

void Image::storeEncoded(uint8_t* texel, const glm::vec4& value, const Profile& profile) {
  const DefaultFloatingPoint fp;
  encodeTexel(format_, value, profile, texel);
}

void Image::storeRow(int y, const int* xs, int n, const glm::vec4* values, const Profile& profile) {
  const DefaultFloatingPoint fp;
  uint8_t* row = texel(0, y);
  for (int i = 0; i < n; ++i) encodeTexel(format_, values[i], profile, row + size_t(xs[i]) * texelBytes_);
}

namespace {

// `bytes` bytes at `out` (a whole number of texels) filled with the texel at `texel`, by
// doubling: the filled prefix copied onto the rest, in ever larger blocks.
void fillWithTexel(uint8_t* out, size_t bytes, const uint8_t* texel, size_t texelBytes) {
  std::memcpy(out, texel, texelBytes);
  for (size_t filled = texelBytes; filled < bytes; filled *= 2) std::memcpy(out + filled, out, std::min(filled, bytes - filled));
}

}  // namespace

void Image::clear(const glm::vec4& value, const Profile& profile) {
  const DefaultFloatingPoint fp;
  uint8_t texel[16];
  encodeTexel(format_, value, profile, texel);
  if (!bytes_.empty()) fillWithTexel(bytes_.data(), bytes_.size(), texel, texelBytes_);
}

void Image::clearRect(int x0, int y0, int x1, int y1, const uint8_t* texel) {
  if (x0 >= x1) return;
  for (int y = y0; y < y1; ++y) fillWithTexel(this->texel(x0, y), size_t(x1 - x0) * texelBytes_, texel, texelBytes_);
}

void Image::copyTexels(const Image& source) {
  if (!(format_ == source.format_) || width_ != source.width_ || height_ != source.height_)
    throw std::logic_error("Image::copyTexels: the images differ in format or size");
  std::memcpy(bytes_.data(), source.bytes_.data(), bytes_.size());
}

bool Image::sameBits(const Image& other) const {
  return format_ == other.format_ && width_ == other.width_ && height_ == other.height_ && bytes_ == other.bytes_;
}

}  // namespace oitref
