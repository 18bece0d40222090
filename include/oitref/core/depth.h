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
#include <type_traits>
#include <utility>
#include <vector>

#include "oitref/core/texture.h"
#include "oitref/core/unorm.h"

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
// The same with the UNORM rule for d16/d24 named (encodeDepthAs).
inline uint32_t encodeDepth(double windowZ, DepthFormat format, UnormRounding rounding);
double decodeDepth(uint32_t stored, DepthFormat format);
// A stored depth as a shader's texelFetch of the depth texture returns it under the profile's
// texture unit: exact, decodeDepth rounded once to fp32; llvmpipe (d16, d24), the code converted
// to float and multiplied by fp32(1/(2^n − 1)) (gallivm/lp_bld_conv.c,
// lp_build_unsigned_norm_to_float, for n ≤ 24). d32f is its own bits either way.
inline float fetchDepthTexel(uint32_t stored, DepthFormat format, TextureFiltering rule);
// The stored depth a shader compares with when it reads the texel (fetchDepthTexel) and rounds
// it back to a code, round-to-nearest-even of v·(2^n − 1) in double (depth peeling's GLSL); the
// stored value itself for d32f, and for the exact rule, whose round trip gives it back. Under
// llvmpipe's, codes near 1 can come back one or two away.
inline uint32_t depthCodeAsFetched(uint32_t stored, DepthFormat format, TextureFiltering rule);
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
  // The storage of pixel (x, y): uint16_t for d16, else uint32_t (the depth kernels' rows).
  void* texel(int x, int y) { return const_cast<void*>(std::as_const(*this).texel(x, y)); }
  const void* texel(int x, int y) const {
    const size_t i = size_t(y) * width_ + x;
    return format_ == DepthFormat::D16 ? static_cast<const void*>(&d16_[i]) : static_cast<const void*>(&words_[i]);
  }
  void store(int x, int y, uint32_t v) {
    const size_t i = size_t(y) * width_ + x;
    if (format_ == DepthFormat::D16) d16_[i] = uint16_t(v);
    else words_[i] = v;
  }
  double depth(int x, int y) const { return decodeDepth(load(x, y), format_); }
  void clear(double z);
  // The pixels [x0, x1) × [y0, y1) get the stored value `v` (encodeDepth's): a draw's clear, one
  // tile at a time (Framebuffer::clearDepth).
  void clearRect(int x0, int y0, int x1, int y1, uint32_t v);
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
// The rule once, for a format known when compiled, on one depth (D = double) or four
// (D = lanes::d4, the span kernels of a draw).
// `Rounding` is the UNORM conversion's rule (unorm.h) for d16 and d24: ExactNearestEven rounds the
// exact product z·(2^n − 1); Fp32Product rounds it to fp32 first, as llvmpipe converts its fp32
// window z (lp_bld_depth.c, lp_build_depth_stencil_test → lp_build_clamped_float_to_unsigned_norm:
// d24 is n = mantissa + 1, iround(z·16777215.0f); d16 adds 2^7 to z·(65535/65536) and keeps the
// low 16 bits, which is the same integer). z must then be an fp32 value.
template <DepthFormat Format, typename D = double, UnormRounding Rounding = UnormRounding::ExactNearestEven>
inline typename lanes::With<D>::Uint encodeDepthAs(D windowZ) {
  using L = lanes::With<D>;
  const D one = lanes::splat<D>(1.0), zero = lanes::splat<D>(0.0);
  const D z = windowZ > zero ? (windowZ < one ? windowZ : one) : zero;  // the depth range; NaN -> 0
  if constexpr (Format == DepthFormat::D32F) {
    return std::bit_cast<typename L::Uint>(lanes::convert<typename L::Float>(z));
  } else {  // the product below 2^24, ties to even
    const D maxCode = lanes::splat<D>(Format == DepthFormat::D16 ? 0xffffu : 0xffffffu);
    static_assert(Rounding != UnormRounding::NvidiaFixed, "no depth rule of that name");
    if constexpr (Rounding == UnormRounding::Fp32Product) {
      using F = typename L::Float;
      const D product = lanes::convert<D>(lanes::convert<F>(z) * lanes::convert<F>(maxCode));
      if constexpr (lanes::isVector<D>) {
        typedef uint32_t u8 __attribute__((vector_size(32)));
        const u8 bits = (u8)(product + lanes::splat<D>(0x1p52));
        return __builtin_shufflevector(bits, bits, 0, 2, 4, 6);
      } else {
        return lanes::convert<typename L::Uint>(roundHalfEven<typename L::Int>(product));
      }
    }
    if constexpr (lanes::isVector<D>) {
      // roundHalfEven in lanes without conversions: p + 2^52 (0 ≤ p < 2^51) rounds p to an
      // integer, ties to even, in the default rounding mode (fp_environment.h), and holds that
      // integer in its low mantissa bits.
      typedef uint32_t u8 __attribute__((vector_size(32)));
      const u8 bits = (u8)(z * maxCode + lanes::splat<D>(0x1p52));
      return __builtin_shufflevector(bits, bits, 0, 2, 4, 6);
    } else {
      return lanes::convert<typename L::Uint>(roundHalfEven<typename L::Int>(z * maxCode));
    }
  }
}
inline uint32_t encodeDepth(double windowZ, DepthFormat format, UnormRounding rounding) {
  const bool fp32 = rounding == UnormRounding::Fp32Product;
  switch (format) {
    case DepthFormat::D16:
      return fp32 ? encodeDepthAs<DepthFormat::D16, double, UnormRounding::Fp32Product>(windowZ)
                  : encodeDepthAs<DepthFormat::D16>(windowZ);
    case DepthFormat::D24:
      return fp32 ? encodeDepthAs<DepthFormat::D24, double, UnormRounding::Fp32Product>(windowZ)
                  : encodeDepthAs<DepthFormat::D24>(windowZ);
    case DepthFormat::D32F: break;
  }
  return encodeDepthAs<DepthFormat::D32F>(windowZ);
}
inline uint32_t encodeDepth(double windowZ, DepthFormat format) {
  return encodeDepth(windowZ, format, UnormRounding::ExactNearestEven);
}
// The largest code of a UNORM depth format, 2^n − 1 (d16, d24).
constexpr double depthMaxCode(DepthFormat format) { return format == DepthFormat::D16 ? 65535.0 : 16777215.0; }
// llvmpipe's texelFetch of a d16/d24 code, and the code a shader rounds it back to
// (fetchDepthTexel, depthCodeAsFetched), on one code (U = uint32_t) or four (U = lanes::u4).
template <typename U>
inline auto llvmpipeDepthTexel(U stored, double maxCode) {
  using F = std::conditional_t<lanes::isVector<U>, lanes::f4, float>;
  const float reciprocal = float(1.0 / maxCode);  // fp32(1/(2^n − 1))
  return lanes::convert<F>(stored) * reciprocal;
}
template <typename U>
inline U llvmpipeDepthCodeAsFetched(U stored, double maxCode) {
  using D = std::conditional_t<lanes::isVector<U>, lanes::d4, double>;
  const D p = lanes::convert<D>(llvmpipeDepthTexel(stored, maxCode)) * lanes::splat<D>(maxCode);
  if constexpr (lanes::isVector<U>) {  // p + 2^52 rounds p (< 2^51) to an integer, ties to even (encodeDepthAs)
    typedef uint32_t u8 __attribute__((vector_size(32)));
    const u8 bits = (u8)(p + lanes::splat<D>(0x1p52));
    return __builtin_shufflevector(bits, bits, 0, 2, 4, 6);
  } else {
    return roundHalfEven(p);
  }
}
inline float fetchDepthTexel(uint32_t stored, DepthFormat format, TextureFiltering rule) {
  if (format == DepthFormat::D32F) return std::bit_cast<float>(stored);
  if (rule == TextureFiltering::Llvmpipe) return llvmpipeDepthTexel(stored, depthMaxCode(format));
  return float(decodeDepth(stored, format));
}
inline uint32_t depthCodeAsFetched(uint32_t stored, DepthFormat format, TextureFiltering rule) {
  if (format == DepthFormat::D32F || rule != TextureFiltering::Llvmpipe) return stored;
  return llvmpipeDepthCodeAsFetched(stored, depthMaxCode(format));
}

// The rule once, for a format and function known when compiled, on one stored value (U =
// uint32_t: bool) or four (U = lanes::u4: −1/0 lanes).
template <CompareFunc Func, DepthFormat Format, typename U>
inline auto depthTestPassesAs(U fragment, U stored) {
  using Float = std::conditional_t<lanes::isVector<U>, lanes::f4, float>;
  // Clamped non-negative fp32 values order like their bit patterns, but compare as floats so the
  // rule reads as written.
  const auto less = Format == DepthFormat::D32F ? std::bit_cast<Float>(fragment) < std::bit_cast<Float>(stored)
                                                : fragment < stored;
  const auto equal = Format == DepthFormat::D32F ? std::bit_cast<Float>(fragment) == std::bit_cast<Float>(stored)
                                                 : fragment == stored;
  if constexpr (Func == CompareFunc::Never) return lanes::both(less, lanes::negate(less));
  else if constexpr (Func == CompareFunc::Less) return less;
  else if constexpr (Func == CompareFunc::Equal) return equal;
  else if constexpr (Func == CompareFunc::LEqual) return lanes::either(less, equal);
  else if constexpr (Func == CompareFunc::Greater) return lanes::both(lanes::negate(less), lanes::negate(equal));
  else if constexpr (Func == CompareFunc::NotEqual) return lanes::negate(equal);
  else if constexpr (Func == CompareFunc::GEqual) return lanes::negate(less);
  else return lanes::either(less, lanes::negate(less));  // Always
}

inline bool depthTestPasses(CompareFunc func, uint32_t fragment, uint32_t stored, DepthFormat format) {
  auto as = [&]<CompareFunc Func>() -> bool {
    switch (format) {
      case DepthFormat::D16: return depthTestPassesAs<Func, DepthFormat::D16>(fragment, stored);
      case DepthFormat::D24: return depthTestPassesAs<Func, DepthFormat::D24>(fragment, stored);
      case DepthFormat::D32F: break;
    }
    return depthTestPassesAs<Func, DepthFormat::D32F>(fragment, stored);
  };
  switch (func) {
    case CompareFunc::Never: return as.template operator()<CompareFunc::Never>();
    case CompareFunc::Less: return as.template operator()<CompareFunc::Less>();
    case CompareFunc::Equal: return as.template operator()<CompareFunc::Equal>();
    case CompareFunc::LEqual: return as.template operator()<CompareFunc::LEqual>();
    case CompareFunc::Greater: return as.template operator()<CompareFunc::Greater>();
    case CompareFunc::NotEqual: return as.template operator()<CompareFunc::NotEqual>();
    case CompareFunc::GEqual: return as.template operator()<CompareFunc::GEqual>();
    case CompareFunc::Always: break;
  }
  return as.template operator()<CompareFunc::Always>();
}

}  // namespace oitref
