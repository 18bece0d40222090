// Profiles: named sets of conversion and blending choices, so oitref can reproduce a specific
// implementation where the specifications leave a choice (see docs/rules.md).
//
//  exact     every conversion rounds to nearest, ties to even, from the exact value; UNORM
//            blending in fp32 as GL 4.6 §17.3.6 writes it. The reference default.
//  llvmpipe  Mesa's software GL driver: fp16 and F11/F10 stores round toward zero (finite
//            overflow -> largest finite value); UNORM conversion rounds the fp32 product
//            f·(2^b−1); UNORM8 targets blend in 8-bit integers on the quantised source with
//            a·b/255 computed as t = a·b + 128; (t + (t >> 8)) >> 8.
//
// A profile string may override single fields: "exact,fp16=rtz", "llvmpipe,unorm=exact".
// Keys: fp16, packed (F11/F10), minifloat (user minifloat formats): rne|rtz;
// unorm: exact|fp32; unorm8_blend: float|integer.
#pragma once

#include <string>

#include "oitref/minifloat.h"
#include "oitref/unorm.h"

namespace oitref {

enum class Unorm8Blend : uint8_t { Float, Integer };

struct Profile {
  std::string name = "exact";
  Rounding fp16 = Rounding::NearestEven;
  Rounding packedFloat = Rounding::NearestEven;  // the F11/F10 channels of r11g11b10f
  Rounding minifloat = Rounding::NearestEven;    // user-defined minifloat formats
  UnormRounding unorm = UnormRounding::ExactNearestEven;
  Unorm8Blend unorm8Blend = Unorm8Blend::Float;

  bool operator==(const Profile&) const = default;
  std::string describe() const;  // every field, e.g. for reports and failing tests
};

Profile exactProfile();
Profile llvmpipeProfile();
// "exact", "llvmpipe", optionally followed by ",key=value" overrides. Throws
// std::invalid_argument naming the bad part and the valid choices.
Profile parseProfile(const std::string& text);

}  // namespace oitref
