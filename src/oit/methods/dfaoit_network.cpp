#include "methods/dfaoit_network.h"

#include <algorithm>

#include "methods/det_math.h"
#include "methods/dfaoit_weights.h"

namespace oitref::methods {

void dfaoitFeatures(const glm::vec3& nearestTwo, const glm::vec3& restColour, float restAlpha, float count,
                    const glm::vec3& premultipliedSum, float x[kDfaoitInputs]) {
  const float rest = count - 2.0f;
  x[0] = nearestTwo.r, x[1] = nearestTwo.g, x[2] = nearestTwo.b;
  x[3] = restAlpha / rest;
  x[4] = restColour.r / rest, x[5] = restColour.g / rest, x[6] = restColour.b / rest;
  x[7] = premultipliedSum.r, x[8] = premultipliedSum.g, x[9] = premultipliedSum.b;
}

glm::vec3 dfaoitEvaluate(const DfaoitParameters& p, const float x[kDfaoitInputs]) {
  const float* w1 = p.data();
  const float* b1 = w1 + kDfaoitHidden1 * kDfaoitInputs;
  const float* w2 = b1 + kDfaoitHidden1;
  const float* b2 = w2 + kDfaoitHidden2 * kDfaoitHidden1;
  const float* w3 = b2 + kDfaoitHidden2;
  const float* b3 = w3 + kDfaoitOutputs * kDfaoitHidden2;
  float h1[kDfaoitHidden1], h2[kDfaoitHidden2];
  for (int i = 0; i < kDfaoitHidden1; ++i) {
    float s = b1[i];
    for (int j = 0; j < kDfaoitInputs; ++j) s += w1[i * kDfaoitInputs + j] * x[j];
    h1[i] = std::max(s, 0.0f);
  }
  for (int i = 0; i < kDfaoitHidden2; ++i) {
    float s = b2[i];
    for (int j = 0; j < kDfaoitHidden1; ++j) s += w2[i * kDfaoitHidden1 + j] * h1[j];
    h2[i] = std::max(s, 0.0f);
  }
  glm::vec3 y;
  for (int i = 0; i < kDfaoitOutputs; ++i) {
    float s = b3[i];
    for (int j = 0; j < kDfaoitHidden2; ++j) s += w3[i * kDfaoitHidden2 + j] * h2[j];
    y[i] = float(1.0 / (1.0 + detExp(-double(s))));
  }
  return y;
}

const DfaoitParameters& dfaoitTrainedParameters() {
  static const DfaoitParameters p = [] {
    DfaoitParameters q{};
    std::copy(std::begin(kDfaoitWeights), std::end(kDfaoitWeights), q.begin());
    return q;
  }();
  return p;
}

}  // namespace oitref::methods
