// FragmentStage's proofs over a rectangle of a triangle's pixels (fragment_ops.h): B bounded,
// which makes a flat attribute its vertices' value at every pixel, and the window depth's plane
// with its margin. Once per triangle and tile, not per fragment.
#include <algorithm>
#include <cmath>
#include <limits>

#include "pipeline/fragment_ops.h"

namespace oitref::detail {

// Proof that B = |b̂0| + |b̂1| + |b̂2| < 2^20 at every pixel centre of the rectangle, B as
// interpolateViewDepth and interpolateBarycentrics compute it (hats: computed values; u = 2^−53).
// k_i(x, y) = I_i0·x_n + I_i1·y_n + I_i2 and s = Σ k_i are linear in the pixel (x_n = x·sx + ox
// with the stored sx, ox, exactly), so over the rectangle |k_i| is greatest, and |s| least where s
// keeps one sign, at its corners. With X ≥ |x_n|, Y ≥ |y_n| and T_i = |I_i0|·X + |I_i1|·Y + |I_i2|,
// the computed k̂_i (x̂_n, ŷ_n rounded twice, then two products and two sums) lie within 6u·T_i of
// k_i, and ŝ = (k̂0 + k̂1) + k̂2 within 6u·ΣT + γ2·Σ|k̂_i| of s. The corners' own k̃, s̃ are computed
// the same way, so with K = Σ(max|k̃_i| + 12u·T_i) ≥ Σ|k̂_i| and S = min|s̃| − 32u·(ΣT + K) ≤ |ŝ|
// (s̃ of one sign at the four corners, S > 0), B ≤ (K/S)·(1 + u)^4 (ŵ = 1/ŝ, b̂_i = k̂_i·ŵ and two
// sums, one rounding each), below 2^20 where K < 2^19·S. A NaN or an infinity fails a comparison.
bool FragmentStage::barycentricsBoundedOn(const TriangleInterpolation& t, const double (&ndc)[4], const PixelRect& r,
                                          RectangleBound* bound) {
  if (r.x0 >= r.x1 || r.y0 >= r.y1) return false;
  const double xs[2] = {double(r.x0), double(r.x1 - 1)}, ys[2] = {double(r.y0), double(r.y1 - 1)};
  const double X = std::max(std::fabs(xs[0]), std::fabs(xs[1])) * std::fabs(ndc[0]) + std::fabs(ndc[1]);
  const double Y = std::max(std::fabs(ys[0]), std::fabs(ys[1])) * std::fabs(ndc[2]) + std::fabs(ndc[3]);
  double T = 0.0, largest[3] = {0.0, 0.0, 0.0}, leastS = std::numeric_limits<double>::infinity();
  for (const auto& row : t.inverse) T += std::fabs(row[0]) * X + std::fabs(row[1]) * Y + std::fabs(row[2]);
  int positive = 0, negative = 0;
  for (double y : ys) {
    const double yn = y * ndc[2] + ndc[3];
    for (double x : xs) {
      const double xn = x * ndc[0] + ndc[1];
      double s = 0.0;
      for (int i = 0; i < 3; ++i) {
        const double k = inverseRowAt(t.inverse[i], xn, yn);
        largest[i] = std::max(largest[i], std::fabs(k));
        s = i == 0 ? k : s + k;  // (k0 + k1) + k2
      }
      positive += s > 0.0, negative += s < 0.0;
      leastS = std::min(leastS, std::fabs(s));
    }
  }
  constexpr double u = 0x1p-53;
  const double K = (largest[0] + largest[1]) + largest[2] + 12.0 * u * T;
  const double S = leastS - 32.0 * u * (T + K);
  const bool bounded = (positive == 4 || negative == 4) && S > 0.0 && K < 0x1p19 * S;
  if (bounded && bound) {
    bound->T = T;
    for (int i = 0; i < 3; ++i) bound->K[i] = largest[i] + 12.0 * u * T;
  }
  return bounded;
}

// The window z is affine in the pixel: with b_i = k_i·w and w = 1/Σk_i, z_w = ½·(Σ b_i·c_i)/w + ½
// = ½·Σ c_i·k_i + ½, and k_i = I_i0·x_n + I_i1·y_n + I_i2, so z_w = ½·(a·x_n + b·y_n + c) + ½ with
// a = Σ c_i·I_i0, b = Σ c_i·I_i1, c = Σ c_i·I_i2 (c_i the clip z). interpolate() computes it the
// long way; its ẑ_w differs from the exact Z = ½·Σ c_i·k_i + ½ by at most 3u·Σ|c_i|·T_i (the k̂_i's
// own errors, halved) + 3u·Σ|c_i|·|k̂_i| (b̂_i, the products, two sums and the quotient by ŵ: ŵ
// itself cancels, five roundings) + u·|ẑ_w| (the last sum; ½·q̂ is exact but where it underflows,
// by 2^−1075 at most). The plane's value, computed with rounded a, b, c (three roundings each) from
// x̂_n, ŷ_n, differs from Z by at most 4u·Σ|c_i|·T_i + u·|z_w|, half of its ndc error 8u·Σ|c_i|·T_i.
// With |k̂_i| ≤ K_i over the rectangle (barycentricsBoundedOn) and |Z| ≤ ½·Σ|c_i|·K_i + ½, the
// margin error = 32u·(Σ|c_i|·(T + K_i) + 1) + 2^−1000 covers both, the rounding of z ± error
// included; it is set up only where error < 2^−30, which also bounds every value involved.
bool FragmentStage::windowDepthPlane(const TriangleInterpolation& t, const RectangleBound& bound, WindowDepthPlane& out) {
  const double(&inverse)[3][3] = t.inverse;
  const double* clipZ = t.clipZ;
  double plane[3];
  for (int j = 0; j < 3; ++j) plane[j] = (clipZ[0] * inverse[0][j] + clipZ[1] * inverse[1][j]) + clipZ[2] * inverse[2][j];
  double magnitude = 1.0;
  for (int i = 0; i < 3; ++i) magnitude += std::fabs(clipZ[i]) * (bound.T + bound.K[i]);
  const double error = 32.0 * 0x1p-53 * magnitude + 0x1p-1000;
  if (!(error < 0x1p-30) || !std::isfinite(plane[0] + plane[1] + plane[2])) return false;
  out = {plane[0], plane[1], plane[2], error};
  return true;
}

}  // namespace oitref::detail
