// IEEE binary16 ("half"), the storage of the r16f/rg16f/rgba16f targets.
//
// encodeHalf follows the minifloat contract (include/oitref/core/minifloat.h) for kHalfSpec:
// round-to-nearest-even or toward-zero, denormals produced, overflow -> ±inf (nearest-even) or
// ±65504 (toward zero), NaN -> quiet NaN keeping sign and top payload bits. decodeHalf is exact.
//
// Built with OITREF_F16C these use the x86 F16C instructions (VCVTPS2PH with an explicit
// rounding immediate, VCVTPH2PS); otherwise the portable minifloat converter. The test
// "fp16: F16C and the portable converter agree" checks both give identical bits.
#pragma once

#include <cstdint>

#include "oitref/core/minifloat.h"

namespace oitref {

uint16_t encodeHalf(float value, Rounding rounding = Rounding::NearestEven);
float decodeHalf(uint16_t bits);

// The portable path, always available (for tests and for builds without F16C).
uint16_t encodeHalfPortable(float value, Rounding rounding);
float decodeHalfPortable(uint16_t bits);

// True when this build converts with F16C.
bool halfUsesF16C();
// True when the CPU running this has F16C (CPUID leaf 1, ECX bit 29); false off x86.
bool cpuHasF16C();

}  // namespace oitref
