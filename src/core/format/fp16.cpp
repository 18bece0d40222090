#include "oitref/core/fp16.h"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

#include "format/fp16_inline.h"

namespace oitref {

uint16_t encodeHalf(float value, Rounding rounding) { return detail::encodeHalfInline(value, rounding); }
float decodeHalf(uint16_t bits) { return detail::decodeHalfInline(bits); }

uint16_t encodeHalfPortable(float value, Rounding rounding) {
  return static_cast<uint16_t>(encodeMinifloat(value, kHalfSpec, rounding));
}
float decodeHalfPortable(uint16_t bits) { return decodeMinifloat(bits, kHalfSpec); }

bool cpuHasF16C() {
#if defined(__x86_64__) || defined(__i386__)
  unsigned a = 0, b = 0, c = 0, d = 0;
  return __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C);
#else
  return false;
#endif
}

bool halfUsesF16C() {
#if defined(OITREF_HAVE_F16C)
  return true;
#else
  return false;
#endif
}

}  // namespace oitref
