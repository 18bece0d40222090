#include "oitref/core/depth.h"
#include "oitref/core/unorm.h"

#include <bit>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace oitref {
namespace {

constexpr const char* kCompareNames[] = {"never", "less", "equal", "lequal", "greater", "notequal", "gequal", "always"};

uint32_t fixedMax(DepthFormat f) { return f == DepthFormat::D16 ? 0xffffu : 0xffffffu; }

}  // namespace

const char* toString(DepthFormat f) {
  switch (f) {
    case DepthFormat::D16: return "d16";
    case DepthFormat::D24: return "d24";
    case DepthFormat::D32F: return "d32f";
  }
  return "?";
}

const char* toString(CompareFunc f) { return kCompareNames[int(f)]; }

DepthFormat parseDepthFormat(const std::string& name) {
  if (name == "d16") return DepthFormat::D16;
  if (name == "d24") return DepthFormat::D24;
  if (name == "d32f") return DepthFormat::D32F;
  throw std::invalid_argument("unknown depth format '" + name + "' (valid: d16, d24, d32f)");
}

CompareFunc parseCompareFunc(const std::string& name) {
  for (int i = 0; i < 8; ++i)
    if (name == kCompareNames[i]) return CompareFunc(i);
  throw std::invalid_argument("unknown depth function '" + name +
                              "' (valid: never, less, equal, lequal, greater, notequal, gequal, always)");
}

double decodeDepth(uint32_t stored, DepthFormat format) {
  if (format == DepthFormat::D32F) return double(std::bit_cast<float>(stored));
  return double(stored) / double(fixedMax(format));
}

DepthBuffer::DepthBuffer(DepthFormat format, int width, int height)
    : format_(format), width_(width), height_(height) {
  const size_t n = size_t(width) * size_t(height);
  if (format == DepthFormat::D16) d16_.resize(n);
  else words_.resize(n);
  clear(1.0);
}

void DepthBuffer::clearRect(int x0, int y0, int x1, int y1, uint32_t v) {
  for (int y = y0; y < y1 && x0 < x1; ++y) {
    const size_t i = size_t(y) * width_ + size_t(x0), n = size_t(x1 - x0);
    if (format_ == DepthFormat::D16) std::fill_n(d16_.begin() + std::ptrdiff_t(i), n, uint16_t(v));
    else std::fill_n(words_.begin() + std::ptrdiff_t(i), n, v);
  }
}

void DepthBuffer::clear(double z) {
  const uint32_t v = encodeDepth(z, format_);
  std::fill(d16_.begin(), d16_.end(), uint16_t(v));
  std::fill(words_.begin(), words_.end(), v);
}

}  // namespace oitref
