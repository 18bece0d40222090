// Stage 5, before the early depth test: an interval that provably holds the window z that the
// fragment stage computes (fragment_ops.h, the expressions of its header comment, in double) at
// every pixel of a run [x0, x1) of one row, from a few scalar operations per run. Where every
// depth code of that interval fails the test against every stored depth of the run
// (depth_batch.h: DepthRunRejects), the run is rejected without interpolating it: a GPU's
// hierarchical depth test, made exact. It rejects only fragments that the per-fragment test
// rejects, so no bit changes; where the bound cannot be proven (below) it says so and the run is
// tested fragment by fragment as before.
//
// Why the interval holds. Write u = 2^−53 and, for the pixel's computed NDC x (X: computed as in
// FragmentStage::interpolate, so X is monotone in the column) and the row's Yn, the exact reals
//   k*_i = inv_i0·X + inv_i1·Yn + inv_i2,   L* = Σ k*_i·z_i   (z_i: the clip z of vertex i)
//   M = Σ_i (|inv_i0·X| + |inv_i1·Yn| + |inv_i2|),   T = Σ_i |z_i|·(|inv_i0·X| + |inv_i1·Yn| + |inv_i2|).
// The computed k_i = k*_i + δ_i with |δ_i| ≤ 3u·M_i. The stage computes K = Σ k_i, w = 1/K,
// b_i = k_i·w, s = Σ b_i·z_i and d = s / w; with each rounding a factor (1 + ε), |ε| ≤ u,
//   d = ((q_0 + q_1)(1 + α) + q_2)(1 + β)(1 + γ),   q_i = k_i·z_i·(1 + ε_i)(1 + η_i):
// the w of b_i and the w of the division cancel exactly, whatever w is, so long as it is finite
// and non-zero and nothing overflows or underflows. Hence |d − L*| ≤ 9u·T (to first order), and
// the window z = ½·d + ½ (one more rounding) lies within 5u·T + u·(|z| + 1) of ½·L* + ½.
// L* is affine in X and T, M grow with |X|, so over a run their extremes lie at its two ends.
// The interval is ½·L*(ends) + ½ widened by 2^−44·(T + 1) (here L* and T are evaluated in double,
// with errors of a few u·T) and by 2^−800·(1 + Σ|z_i|), which covers underflow: an operation
// whose result is subnormal errs by up to 2^−1075 absolutely, and the division by w scales that by
// at most |K| ≤ 2^200 (required below).
// What makes w finite and the factors (1 + ε) valid: K's computed value stays within 12u·M of
// K* = Σ k*_i, which is affine in X too; when K* has one sign at both ends of the run and
// M ≤ 2^44·min|K*(ends)|, K's computed value is at least half of min|K*| away from zero at every
// pixel, so |w| ≤ 2/min|K*|, |b_i| ≤ 2^46 and nothing overflows; |K*| ≤ 2^200 bounds the
// underflow's scaling. Runs that do not meet this, or whose numbers are not finite, get no
// interval (a triangle seen nearly edge-on, a pixel whose surface point lies near the eye plane).
#pragma once

#include <algorithm>
#include <cmath>

#include "pipeline/setup.h"

namespace oitref::detail {

class WindowDepthBounds {
 public:
  // Per triangle: its interpolation set-up (setup.h).
  void beginTriangle(const TriangleInterpolation& t) {
    inverse_ = t.inverse;
    const double* z = t.clipZ;
    a_ = kx_ = tx_ = mx_ = zsum_ = 0.0;
    for (int i = 0; i < 3; ++i) {
      a_ += inverse_[i][0] * z[i];
      kx_ += inverse_[i][0];
      tx_ += std::fabs(inverse_[i][0]) * std::fabs(z[i]);
      mx_ += std::fabs(inverse_[i][0]);
      zsum_ += std::fabs(z[i]);
    }
    clipZ_ = z;
  }
  // Per row, at NDC y `yn` (as the stage computes it).
  void beginRow(double yn) {
    b_ = kc_ = tc_ = mc_ = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double c = inverse_[i][1] * yn + inverse_[i][2];
      const double m = std::fabs(inverse_[i][1] * yn) + std::fabs(inverse_[i][2]);
      b_ += c * clipZ_[i];
      kc_ += c;
      tc_ += std::fabs(clipZ_[i]) * m;
      mc_ += m;
    }
  }
  // The run whose first and last pixels have computed NDC x `x0` and `x1` (x0 ≤ x1): true with
  // [zLow, zHigh] holding every pixel's window z, or false where the bound is not proven.
  bool bound(double x0, double x1, double& zLow, double& zHigh) const {
    const double k0 = kx_ * x0 + kc_, k1 = kx_ * x1 + kc_;
    const double kMin = std::min(std::fabs(k0), std::fabs(k1)), kMax = std::max(std::fabs(k0), std::fabs(k1));
    const double ax = std::max(std::fabs(x0), std::fabs(x1));
    const double m = mx_ * ax + mc_, t = tx_ * ax + tc_;
    // !(a ≤ b) rather than a > b: a NaN anywhere refuses.
    if (!((k0 > 0.0 && k1 > 0.0) || (k0 < 0.0 && k1 < 0.0)) || !(m <= kMin * 0x1p44) || !(kMax <= 0x1p200))
      return false;
    const double l0 = a_ * x0 + b_, l1 = a_ * x1 + b_;
    if (!std::isfinite(l0) || !std::isfinite(l1)) return false;
    const double margin = 0x1p-44 * (t + 1.0) + 0x1p-800 * (1.0 + zsum_);
    zLow = 0.5 * std::min(l0, l1) + 0.5 - margin;
    zHigh = 0.5 * std::max(l0, l1) + 0.5 + margin;
    return std::isfinite(zLow) && std::isfinite(zHigh);
  }

 private:
  const double (*inverse_)[3] = nullptr;
  const double* clipZ_ = nullptr;
  // L* = a·X + b, K* = kx·X + kc, T = tx·|X| + tc, M = mx·|X| + mc (the header comment).
  double a_ = 0, kx_ = 0, tx_ = 0, mx_ = 0, zsum_ = 0;
  double b_ = 0, kc_ = 0, tc_ = 0, mc_ = 0;
};

}  // namespace oitref::detail
