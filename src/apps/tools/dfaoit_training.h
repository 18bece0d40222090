// Training of the DFAOIT network (methods/dfaoit_network.h), as the paper does it (§3.2):
// per-pixel features and exact targets from A-buffer renders of training scenes — scenes of its
// own, none of the built-in ones the study evaluates on — then Adam (learning rate 1e-3) on the
// mean squared error in batches of 4096. Everything is seeded and sequential: the same weights
// on every run and machine.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "methods/dfaoit_network.h"
#include "oitref/oit/method.h"

namespace oitref::tools {

struct DfaoitSample {
  float x[methods::kDfaoitInputs];
  float target[methods::kDfaoitOutputs];  // the colour the transparent layers add (over black)
};

// Sixteen scenes, 128×128 pixels: eight particle clouds of one to three colours (α uniform in
// [0.01, 0.85] per cloud, softened towards each particle's rim) and eight boxes of 20–60 flat
// quads (one colour and α in [0.01, 0.85] each), depth complexity up to about 50.
std::vector<Scene> dfaoitTrainingScenes();

// Every pixel with more than two transparent fragments (the others are exact in the method).
std::vector<DfaoitSample> dfaoitDataset(const std::vector<Scene>& scenes, Renderer& renderer);

struct DfaoitTraining {
  int epochs = 3000, batch = 4096;  // the paper's
  double learningRate = 1e-3;
  uint32_t seed = 1;
};

// Returns the trained parameters; progress(epoch, mean loss of the epoch) after every epoch.
methods::DfaoitParameters trainDfaoit(const std::vector<DfaoitSample>& samples, const DfaoitTraining& options,
                                      const std::function<void(int, double)>& progress);

// The weights as the C++ header src/oit/methods/dfaoit_weights.h, `provenance` in its comment.
std::string dfaoitWeightsHeader(const methods::DfaoitParameters& p, const std::string& provenance);

}  // namespace oitref::tools
