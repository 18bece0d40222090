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

#include "oitref/format.h"
#include "oitref/profile.h"

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

  // texelFetch semantics: the stored value decoded exactly.
  // The fp32 layouts are fetched inline: their decoding is the copy (missing channels 0, alpha 1,
  // as every decoder gives); through the decoder's pointer, the call cost a composite 10 %.
  glm::vec4 fetch(int x, int y) const {
    const uint8_t* t = texel(x, y);
    glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f);
    switch (float32Channels_) {
      case 4: std::memcpy(&v, t, 16); return v;
      case 2: std::memcpy(&v, t, 8); return v;
      case 1: std::memcpy(&v, t, 4); return v;
      default: return decoder_(format_, t);
    }
  }
  // Stores value converted by the format's rule under the profile (no blending, all channels).
  void store(int x, int y, const glm::vec4& value, const Profile& profile);
  // glClearBuffer: every texel gets the converted clear value.
  void clear(const glm::vec4& value, const Profile& profile);

  bool sameBits(const Image& other) const;

 private:
  Format format_{};
  int width_ = 0, height_ = 0;
  size_t texelBytes_ = 0;
  TexelDecoder decoder_ = decodeTexel;
  int float32Channels_ = 0;  // 4, 2 or 1 for rgba32f, rg32f, r32f (fetched inline), else 0
  std::vector<uint8_t> bytes_;
};

// Bytes an image would need, without allocating it (for memory checks).
size_t imageBytes(const Format& format, int width, int height);

}  // namespace oitref
