// llvmpipe's rescaling of UNORM codes between a channel's n bits and the integer width w it
// blends in (Mesa 22.3 lp_state_fs.c, scale_bits; profile key unorm_blend=integer). Used for
// rgb10a2 (n = 10 and 2, w = 16); 8-bit channels blend in their own width and need none.
#pragma once

#include <cstdint>

#include "oitref/core/format.h"
#include "oitref/core/unorm.h"

namespace oitref::detail {

// The integer width llvmpipe blends a UNORM format in: its widest channel rounded up to 8 or 16.
inline int unormBlendWidth(const Format& f) { return f.id == FormatId::RGB10A2 || f.unormBits(0) == 16 ? 16 : 8; }

// n-bit code -> w bits by replicating its bits (n < w).
inline uint32_t widenUnormBits(uint32_t v, int n, int w) {
  if (n >= w) return v;
  const int db = w - n;
  uint32_t r = v << db;
  if (db <= n) return r | (v >> (n - db));
  for (int k = n; k < w; k *= 2) r |= r >> k;  // repeat the bits until w are filled
  return r;
}

// w-bit code -> n bits: a plain right shift when w − n ≤ n ("approximate the rescaling with a
// single shift", i.e. truncation), else ((v >> n)·(2^n − 1) + 2^(w−n−1)) >> (w − n).
inline uint32_t narrowUnormBits(uint32_t v, int w, int n) {
  if (n >= w) return v;
  const int delta = w - n;
  if (delta <= n) return v >> delta;
  return (((v >> n) * ((1u << n) - 1)) + (1u << (delta - 1))) >> delta;
}

// NVIDIA (profile nvidia) computes rgb10a2's alpha as a 10-bit code, like the colour channels, and
// stores its top four bits rounded to two: round((c10 >> 6)·3/15). Measured: the thresholds of
// the stored alpha lie at 10-bit codes 192, 512 and 832 (docs/rules.md, "Profile nvidia").
inline uint32_t nvidiaAlpha2From10(uint32_t c10) { return ((c10 >> 6) + 2) / 5; }

// fp32 -> an n-bit code through the w-bit integer, as llvmpipe writes rgb10a2 channels.
inline uint32_t encodeUnormThroughWidth(float value, int n, int w, UnormRounding rounding) {
  return narrowUnormBits(encodeUnorm(value, w, rounding), w, n);
}

}  // namespace oitref::detail
