// Depth buffers and the depth test (GL 4.6 §17.3.4).
//
// Formats: d16 and d24 are UNORM (k / (2^n − 1)); d24 is stored in the low 24 bits of a 32-bit
// word (as the X8_D24 layout of real GPUs); d32f is an fp32.
// The fragment's window z is clamped to the depth range [0,1] (GL 4.6 §13.8.1) and converted to
// the buffer's format *before* the comparison, as GPUs and dEQP do: d16/d24 by exact
// round-to-nearest-even of z·(2^n − 1) (§2.3.5.2), d32f by rounding to the nearest fp32. The
// comparison then works on the stored representation (integers, or fp32 for d32f). NaN z
// compares as 0.
#pragma once

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "oitref/unorm.h"

namespace oitref {

enum class DepthFormat : uint8_t { D16, D24, D32F };

enum class CompareFunc : uint8_t { Never, Less, Equal, LEqual, Greater, NotEqual, GEqual, Always };

struct DepthState {
  bool testEnabled = false;              // glDisable(GL_DEPTH_TEST)
  CompareFunc func = CompareFunc::Less;  // glDepthFunc(GL_LESS)
  bool writeMask = true;                 // glDepthMask(GL_TRUE)
  bool clamp = false;                    // GL_DEPTH_CLAMP: no near/far clipping, z clamped
  bool operator==(const DepthState&) const = default;
};

const char* toString(DepthFormat f);
const char* toString(CompareFunc f);
DepthFormat parseDepthFormat(const std::string& name);   // "d16", "d24", "d32f"
CompareFunc parseCompareFunc(const std::string& name);   // "less", "lequal", ...

// Window z (double, any value) -> the buffer's stored representation.
inline uint32_t encodeDepth(double windowZ, DepthFormat format);
double decodeDepth(uint32_t stored, DepthFormat format);
// Does a fragment with stored-format depth `fragment` pass against `stored`?
inline bool depthTestPasses(CompareFunc func, uint32_t fragment, uint32_t stored, DepthFormat format);

class DepthBuffer {
 public:
  DepthBuffer(DepthFormat format, int width, int height);  // cleared to 1.0 (GL's default)
  DepthFormat format() const { return format_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // The stored representation (d16: 16 bits, d24: low 24 bits, d32f: fp32 bits).
  uint32_t load(int x, int y) const {
    const size_t i = size_t(y) * width_ + x;
    return format_ == DepthFormat::D16 ? d16_[i] : words_[i];
  }
  void store(int x, int y, uint32_t v) {
    const size_t i = size_t(y) * width_ + x;
    if (format_ == DepthFormat::D16) d16_[i] = uint16_t(v);
    else words_[i] = v;
  }
  double depth(int x, int y) const { return decodeDepth(load(x, y), format_); }
  void clear(double z);
  int bytesPerTexel() const { return format_ == DepthFormat::D16 ? 2 : 4; }
  size_t sizeBytes() const { return size_t(width_) * height_ * bytesPerTexel(); }
  bool allocated() const { return !d16_.empty() || !words_.empty(); }  // false once moved from

 private:
  DepthFormat format_;
  int width_, height_;
  std::vector<uint16_t> d16_;    // d16 storage
  std::vector<uint32_t> words_;  // d24 (X8_D24) and d32f storage
};

// Inline: the fragment stage calls these per fragment, with the format and function fixed per draw.
inline uint32_t encodeDepth(double windowZ, DepthFormat format) {
  const double z = windowZ > 0.0 ? (windowZ < 1.0 ? windowZ : 1.0) : 0.0;  // the depth range; NaN -> 0
  if (format == DepthFormat::D32F) return std::bit_cast<uint32_t>(float(z));
  return roundHalfEven(z * double(format == DepthFormat::D16 ? 0xffffu : 0xffffffu));  // exact product, ties to even
}

inline bool depthTestPasses(CompareFunc func, uint32_t fragment, uint32_t stored, DepthFormat format) {
  // Clamped non-negative fp32 values order like their bit patterns, but compare as floats so the
  // rule reads as written.
  const bool isFloat = format == DepthFormat::D32F;
  const float ff = std::bit_cast<float>(fragment), fs = std::bit_cast<float>(stored);
  const bool less = isFloat ? ff < fs : fragment < stored;
  const bool equal = isFloat ? ff == fs : fragment == stored;
  switch (func) {
    case CompareFunc::Never: return false;
    case CompareFunc::Less: return less;
    case CompareFunc::Equal: return equal;
    case CompareFunc::LEqual: return less || equal;
    case CompareFunc::Greater: return !less && !equal;
    case CompareFunc::NotEqual: return !equal;
    case CompareFunc::GEqual: return !less;
    case CompareFunc::Always: return true;
  }
  return false;
}

}  // namespace oitref
