// Bit layouts of the packed formats (GL 4.6 table 8.8): rgb10a2 as UNSIGNED_INT_2_10_10_10_REV,
// r11g11b10f as UNSIGNED_INT_10F_11F_11F_REV. One definition for the format code and the
// llvmpipe integer blend.
#pragma once

namespace oitref::detail {

inline constexpr int kRgb10a2Shift[4] = {0, 10, 20, 30};
inline constexpr int kRgb10a2Bits[4] = {10, 10, 10, 2};
inline constexpr int kF11F10Shift[3] = {0, 11, 22};

}  // namespace oitref::detail
