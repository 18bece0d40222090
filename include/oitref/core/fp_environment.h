// oitref's arithmetic assumes IEEE defaults: round to nearest even, denormals kept (no FTZ/DAZ
// on x86). A host application may have changed them; oitref's stages (the vertex stage of
// Geometry::fromVertexShader, every pipeline task) run inside this guard, which sets the default
// environment and restores the thread's own on exit.
//
// The guard also wraps per-texel entry points (Image::store, blendIntoTexel), which shaders call
// once per fragment. Saving and loading the whole environment costs more than such a call, so on
// x86-64 the guard first reads the control registers (cheap) and does nothing when they already
// hold the defaults: SSE rounding to nearest, FTZ and DAZ off, every exception masked, and the
// x87 control word's default (extended precision, nearest, masked).
#pragma once

#include <cfenv>
#include <cstdint>

#if defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace oitref {

class DefaultFloatingPoint {
 public:
  DefaultFloatingPoint() {
    if (alreadyDefault()) return;
    changed_ = true;
    std::fegetenv(&saved_);
    std::fesetenv(FE_DFL_ENV);
  }
  ~DefaultFloatingPoint() {
    if (changed_) std::fesetenv(&saved_);
  }
  DefaultFloatingPoint(const DefaultFloatingPoint&) = delete;
  DefaultFloatingPoint& operator=(const DefaultFloatingPoint&) = delete;

 private:
  static bool alreadyDefault() {
#if defined(__x86_64__)
    constexpr uint32_t kMxcsrControl = 0xffc0u;  // every MXCSR bit but the six exception flags
    constexpr uint32_t kMxcsrDefault = 0x1f80u;  // all exceptions masked, nearest, no FTZ/DAZ
    uint16_t x87;
    __asm__("fnstcw %0" : "=m"(x87));
    return (_mm_getcsr() & kMxcsrControl) == kMxcsrDefault && (x87 & 0x1f3fu) == 0x033fu;
#else
    return false;
#endif
  }

  bool changed_ = false;
  std::fenv_t saved_;
};

}  // namespace oitref
