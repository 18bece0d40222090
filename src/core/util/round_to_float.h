// A double rounded to fp32 where the value goes on in double arithmetic.
#pragma once

namespace oitref::util {

// GCC 12 compiles C++ only with -fexcess-precision=fast, under which "it is unpredictable when
// rounding to the types specified in the source code takes place": its SLP vectoriser computed
// double(float(a)) − double(float(b)) as a − b in FragmentStage::quadDerivatives, two fp32
// roundings lost (a texel's level of detail differed between the span and per-fragment paths).
// A value stored to memory is rounded; one that stays in registers between double operations
// must pass through here. The empty asm makes the compiler hold the rounded float itself.
inline float roundToFloat(double v) {
  float f = float(v);
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  asm("" : "+x"(f));
#else
  volatile float kept = f;
  f = kept;
#endif
  return f;
}

}  // namespace oitref::util
