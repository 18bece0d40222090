// A render target: width × height texels of one format, in the format's own bytes.
//
// Coordinates are GL window coordinates: (0,0) is the lower-left texel, row y = 0 is the bottom
// row. Image writers flip to top-row-first on output.
#pragma once

#include <cstddef>
#include <cstdint>
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
  glm::vec4 fetch(int x, int y) const { return decoder_(format_, texel(x, y)); }
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
  std::vector<uint8_t> bytes_;
};

// Bytes an image would need, without allocating it (for memory checks).
size_t imageBytes(const Format& format, int width, int height);

}  // namespace oitref
