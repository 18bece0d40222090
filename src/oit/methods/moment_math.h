// The moment side of moment-based OIT (Münstermann, Krumpen, Klein, Peters 2018): which moments
// a fragment adds, how 16-bit storage quantises them, and how the absorbance in front of a depth
// is reconstructed from them. mboit.cpp and mt.cpp run these inside their passes; the tests call
// them directly.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "methods/polynomial_roots.h"

namespace oitref::methods {

// A moment set: 4, 6 or 8 power moments of the depth z ∈ [−1, 1] (b1…bN, stored as N reals),
// or 2, 3 or 4 trigonometric moments of the phase φ(z) (b_k = e^{ikφ}, stored as 2·count reals:
// real and imaginary parts in turn).
struct MomentSet {
  bool trigonometric = false;
  int count = 4;
  static MomentSet parse(const std::string& name);  // "power4" … "power8", "trig2" … "trig4"
  std::string name() const;
  int reals() const { return trigonometric ? 2 * count : count; }
  // Münstermann et al.'s published β for fp32 and for 16-bit quantised moments.
  float defaultBias(bool quantised) const;
};

// Trigonometric moments map z ∈ [−1, 1] to φ = (z + 1)·(π − θ/2) ∈ [0, 2π − θ]; the wrapping
// zone of angle θ (default 0.1π) between the farthest depth and 2π gives roots there a weight
// ramping linearly from 0 to 1, so that reconstructed layers wrapping around
// behind everything count as behind rather than in front.
struct WrappingZone {
  float angle = 0.0f, phaseScale = 0.0f, rampScale = 0.0f, rampOffset = 0.0f;
  static WrappingZone fromAngle(float angle);
};
// A monotonic (not arc-length) parameter of the point on the unit circle, in [−1, 7).
float circleToParameter(float x, float y);

// What one fragment adds to the moments, before multiplying by its absorbance: the powers
// z, z², …, z^N, or cos kφ, sin kφ for k = 1…count (fp32 products as a shader forms them; the
// phase's cos and sin from det_math.h).
void momentsOf(const MomentSet& set, float z, const WrappingZone& zone, float* out);
// The power moments z … z⁸ as momentsOf forms them (z², z⁴ = z²·z², z⁶ = z⁴·z², odd ones times z),
// inline: the first four as one vector, in registers (MBOIT's usual set).
struct PowerMoments {
  float z, z2, z3, z4, z5, z6, z7, z8;
  explicit PowerMoments(float x) : z(x), z2(x * x), z3(z2 * x), z4(z2 * z2), z5(z4 * x), z6(z4 * z2), z7(z6 * x), z8(z6 * z2) {}
  glm::vec4 firstFour() const { return {z, z2, z3, z4}; }
};

// 16-bit storage: normalised moments are mapped by a fixed matrix and offset into [0, 1] so
// that UNORM16 keeps their useful precision; for trigonometric moments the map is b/2 + 1/2
// (moment_quantisation.cpp).
// The matrices, offsets, bias vectors and β values are the ones published with the paper's
// code (CC0), which the GLSL ports use unchanged.
void quantiseMoments(const MomentSet& set, const float* b, float* q);     // without the offset
void offsetQuantised(const MomentSet& set, float* q, float sign);         // q += sign·offset
void dequantiseMoments(const MomentSet& set, const float* stored, float* b);  // includes −offset

// The bias vector the moments are pulled towards (power moments; trigonometric moments are
// pulled towards 0, i.e. scaled by 1 − β).
const float* powerBiasVector(int count, bool quantised);

// Normalised absorbance in front of depth z from normalised moments b (b0 = 1). `bias` is β,
// `overestimation` the weight of the fragment's own depth. Returns `overestimation` and sets
// *fellBack when the moments cannot be used (the Hankel/Toeplitz matrix is not positive
// definite, or a root or the result is not finite).
float powerMomentAbsorbance(int count, const float* b, float z, float bias, const float* biasVector,
                            float overestimation, bool* fellBack = nullptr);
// powerMomentAbsorbance for n fragments: b[i·count + k] their moments, z[i] their depths. Eight
// fragments run side by side in vector lanes (the same operations per lane, so the same bits):
// the four-moment closed form, and for 6 and 8 moments the solve and the absorbance from the
// roots, whose roots are found four at a time.
void powerMomentAbsorbanceBatch(int count, const float* b, const float* z, int n, float bias, const float* biasVector,
                                float overestimation, float* absorbance, bool* fellBack);
// The moment pulled towards the bias vector: (1 − β)·b + β·bias, as the paper code forms it.
// One value (F = float) or lanes of them (a vector of floats, powerMomentAbsorbanceBatch).
template <typename F>
inline F biasedMoment(F b, float bias, float biasValue) {
  return (1.0f - bias) * b + bias * biasValue;
}
float trigMomentAbsorbance(int count, const float* b, float z, float bias, float overestimation,
                           const WrappingZone& zone, bool* fellBack = nullptr);
// trigMomentAbsorbance for n fragments (b[i·2·count + k], z[i]): the solve and the absorbance from
// the roots for eight fragments side by side in vector lanes, the roots found four at a time, each
// lane computing as it would alone (the same bits).
void trigMomentAbsorbanceBatch(int count, const float* b, const float* z, int n, float bias, float overestimation,
                               const WrappingZone& zone, float* absorbance, bool* fellBack);

}  // namespace oitref::methods
