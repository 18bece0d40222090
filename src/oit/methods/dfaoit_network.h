// The network of Deep and Fast Approximate OIT (Tsopouridis, Vasilakis, Fudos): a multilayer
// perceptron 10 → 32 (ReLU) → 16 (ReLU) → 3 (sigmoid), 931 parameters, that predicts the colour
// the transparent layers add to a pixel (the background term is added exactly beside it), and
// its 10 input features. Used by the method (dfaoit.cpp, in fp32 as a shader would) and by the
// training (tools/dfaoit_training.cpp, in double).
#pragma once

#include <array>
#include <cstddef>

#include <glm/vec3.hpp>

namespace oitref::methods {

inline constexpr int kDfaoitInputs = 10, kDfaoitHidden1 = 32, kDfaoitHidden2 = 16, kDfaoitOutputs = 3;
// Parameters in this order: W1 (32×10, row-major), b1, W2 (16×32), b2, W3 (3×16), b3.
inline constexpr size_t kDfaoitParameters = kDfaoitHidden1 * kDfaoitInputs + kDfaoitHidden1 +
                                            kDfaoitHidden2 * kDfaoitHidden1 + kDfaoitHidden2 +
                                            kDfaoitOutputs * kDfaoitHidden2 + kDfaoitOutputs;
static_assert(kDfaoitParameters == 931);

using DfaoitParameters = std::array<float, kDfaoitParameters>;

// The paper's features (§3.1) of a pixel with n > 2 transparent fragments, front to back
// f_1, f_2, …:
//   x[0..2] = g: the two nearest composited exactly, α1·c1 + (1 − α1)·α2·c2;
//   x[3]    = mean α of the other n − 2 (the paper prints Σ/n; the mean is Σ/(n − 2));
//   x[4..6] = mean colour of the other n − 2;
//   x[7..9] = C_acc = Σ α·c over all n.
// `restColour` and `restAlpha` are the sums over the other n − 2.
void dfaoitFeatures(const glm::vec3& nearestTwo, const glm::vec3& restColour, float restAlpha, float count,
                    const glm::vec3& premultipliedSum, float x[kDfaoitInputs]);

// The network's output in fp32 with a fixed order of operations; the sigmoid's exp is
// det_math.h's, so the bits are the same everywhere.
glm::vec3 dfaoitEvaluate(const DfaoitParameters& p, const float x[kDfaoitInputs]);

// The weights trained by `oitref train-dfaoit` and kept in src/oit/methods/dfaoit_weights.h.
const DfaoitParameters& dfaoitTrainedParameters();

}  // namespace oitref::methods
