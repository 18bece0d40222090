// A render target: width × height texels of one format, in the format's own bytes.
//
// Coordinates are GL window coordinates: (0,0) is the lower-left texel, row y = 0 is the bottom
// row. Image writers flip to top-row-first on output.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include <glm/vec4.hpp>

#include "oitref/core/format.h"
#include "oitref/core/texture.h"
#include "oitref/core/profile.h"
#include "oitref/core/unorm.h"

namespace oitref {

class Image {
 public:
  Image() = default;
  // Throws std::invalid_argument for sizes outside 1..kMaxDimension.
  Image(Format format, int width, int height);

  static constexpr int kMaxDimension = 16384;  // GL's MAX_VIEWPORT_DIMS on common hardware

  const Format& format() const { return format_; }
  int width() const { return width_; }
  int height() const { return height_; }
  size_t bytesPerTexel() const { return texelBytes_; }
  size_t sizeBytes() const { return bytes_.size(); }

  uint8_t* texel(int x, int y) { return bytes_.data() + (size_t(y) * width_ + x) * texelBytes_; }
  const uint8_t* texel(int x, int y) const { return bytes_.data() + (size_t(y) * width_ + x) * texelBytes_; }
  const std::vector<uint8_t>& bytes() const { return bytes_; }

  // How fetch turns 8-bit UNORM codes into floats: k/255 correctly rounded (the default), or as
  // the profile's texture unit does (texture=llvmpipe: decodeUnorm8Llvmpipe). Other formats decode
  // exactly either way. Kept until set again.
  void decodeFetchesAs(TextureFiltering rule);
  // texelFetch semantics: the stored value decoded exactly (decodeFetchesAs).
  // The fp32 and 8-bit UNORM layouts are fetched inline (missing channels 0, alpha 1, as every
  // decoder gives): fp32's decoding is the copy, UNORM8's the decoder's own table of k/255 per
  // channel. Through the decoder's pointer, the call cost a composite 10 % (fp32) and a third of
  // depth peeling's RGBA8 "under" passes' fetch.
  glm::vec4 fetch(int x, int y) const {
    const uint8_t* t = texel(x, y);
    glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f);
    switch (inlineLayout_) {
      case InlineLayout::Float32x4: std::memcpy(&v, t, 16); return v;
      case InlineLayout::Float32x2: std::memcpy(&v, t, 8); return v;
      case InlineLayout::Float32x1: std::memcpy(&v, t, 4); return v;
      case InlineLayout::Unorm8x4: return {unorm8_[t[0]], unorm8_[t[1]], unorm8_[t[2]], unorm8_[t[3]]};
      case InlineLayout::Unorm8x2: v.x = unorm8_[t[0]], v.y = unorm8_[t[1]]; return v;
      case InlineLayout::Unorm8x1: v.x = unorm8_[t[0]]; return v;
      case InlineLayout::None: break;
    }
    return decoder_(format_, t);
  }
  // fetch(xs[i], y) for i < n, into out: the layout decided once for the row, not per texel.
  void fetchRow(int y, const int* xs, int n, glm::vec4* out) const { fetchColumns(texel(0, y), xs, n, out); }
  // fetch(x0 + i, y) for i < n: the texels of a run read as one stream (a full-screen pass's
  // batches, and a span's where every fragment survived), without a column loaded and scaled per
  // texel; fp32's texels copied at once.
  void fetchRun(int y, int x0, int n, glm::vec4* out) const { fetchColumns(texel(x0, y), nullptr, n, out); }
  // The texels x0, x0 + 1, … of row y where the image holds them as fetchRun gives them, read in
  // place: an RGBA32F image's row as vec4s, an R32F image's as the floats fetch(x, y).r gives.
  // Null for every other layout. Valid until the image is written or freed.
  const glm::vec4* float4Run(int y, int x0) const {
    return inlineLayout_ == InlineLayout::Float32x4 ? reinterpret_cast<const glm::vec4*>(texel(x0, y)) : nullptr;
  }
  const float* float1Run(int y, int x0) const {
    return inlineLayout_ == InlineLayout::Float32x1 ? reinterpret_cast<const float*>(texel(x0, y)) : nullptr;
  }
  // Stores value converted by the format's rule under the profile (no blending, all channels).
  // fp32 layouts store the bits as they are (encodeTexel's rule), inline: the per-fragment
  // read-modify-write methods (MLAB, k-buffer, hybrid) store a depth or colour per fragment.
  void store(int x, int y, const glm::vec4& value, const Profile& profile) {
    switch (inlineLayout_) {
      case InlineLayout::Float32x4: std::memcpy(texel(x, y), &value, 16); return;
      case InlineLayout::Float32x2: std::memcpy(texel(x, y), &value, 8); return;
      case InlineLayout::Float32x1: std::memcpy(texel(x, y), &value, 4); return;
      default: storeEncoded(texel(x, y), value, profile);
    }
  }
  // store(xs[i], y, values[i], profile) for i < n: the floating-point environment set once.
  void storeRow(int y, const int* xs, int n, const glm::vec4* values, const Profile& profile);
  // glClearBuffer: every texel gets the converted clear value.
  void clear(const glm::vec4& value, const Profile& profile);
  // The texels [x0, x1) × [y0, y1) get `texel`, a texel of this image's format (encodeTexel's bytes):
  // a draw's clear, one tile at a time (Framebuffer::clearColor).
  void clearRect(int x0, int y0, int x1, int y1, const uint8_t* texel);

  // Every texel's bits from `source`, which has this image's format and size (glCopyImageSubData).
  void copyTexels(const Image& source);

  bool sameBits(const Image& other) const;

 private:
  void storeEncoded(uint8_t* texel, const glm::vec4& value, const Profile& profile);
  // fetchRow's and fetchRun's body: the texels at row + xs[i]·texelBytes, or at row + i·texelBytes
  // where xs is null.
  void fetchColumns(const uint8_t* row, const int* xs, int n, glm::vec4* out) const {
    auto each = [&](auto decode) {
      if (xs)
        for (int i = 0; i < n; ++i) out[i] = decode(row + size_t(xs[i]) * texelBytes_);
      else
        for (int i = 0; i < n; ++i) out[i] = decode(row + size_t(i) * texelBytes_);
    };
    switch (inlineLayout_) {
      case InlineLayout::Float32x4:
        if (!xs) return std::memcpy(out, row, size_t(n) * 16), void();
        return each([](const uint8_t* t) { glm::vec4 v; std::memcpy(&v, t, 16); return v; });
      case InlineLayout::Float32x2:
        return each([](const uint8_t* t) { glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f); std::memcpy(&v, t, 8); return v; });
      case InlineLayout::Float32x1:
        return each([](const uint8_t* t) { glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f); std::memcpy(&v, t, 4); return v; });
      case InlineLayout::Unorm8x4:
        if (!exactUnorm8_)
          return each([this](const uint8_t* t) { return glm::vec4(unorm8_[t[0]], unorm8_[t[1]], unorm8_[t[2]], unorm8_[t[3]]); });
        return each([](const uint8_t* t) {
          glm::vec4 v;
          decodeUnorm8x4(t, &v.x);
          return v;
        });
      default: rowDecoder_(format_, row, texelBytes_, xs, n, out);
    }
  }
  Format format_{};
  int width_ = 0, height_ = 0;
  size_t texelBytes_ = 0;
  TexelDecoder decoder_ = decodeTexel;
  TexelRowDecoder rowDecoder_ = nullptr;
  enum class InlineLayout : uint8_t { None, Float32x4, Float32x2, Float32x1, Unorm8x4, Unorm8x2, Unorm8x1 };
  InlineLayout inlineLayout_ = InlineLayout::None;  // how fetch reads this format
  const float* unorm8_ = nullptr;                   // k/255 for each 8-bit code (the UNORM8 layouts)
  bool exactUnorm8_ = true;                         // unorm8_ is decodeUnorm's table (decodeFetchesAs)
  std::vector<uint8_t> bytes_;
};

// Bytes an image would need, without allocating it (for memory checks).
size_t imageBytes(const Format& format, int width, int height);

}  // namespace oitref
