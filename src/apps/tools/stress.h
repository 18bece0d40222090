// `oitref stress`: the stability atlas. Parametric scenes of n full-screen layers push each
// method and accumulation format to its limits (layer counts 1…4096, α from 0 to 1, depth ranges
// from 1e-3 to 1e5, scaled scenes, HDR colours, dark and bright backgrounds); every cell is
// compared with the exact result, computed in double from the layer list, and its numeric
// failures are recorded (non-finite pixels, accumulators at inf, revealage at 0, MBOIT's moment
// reconstruction falling back).
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "oitref/oit/method.h"

namespace oitref::tools {

// One family of parametric scenes: where the layers are, how the camera sees them, their colours.
struct StressCondition {
  std::string name, description;
  float nearPlane = 0.1f, farPlane = 100.0f;
  float firstDistance = 1, lastDistance = 10;  // layers spread geometrically over this (co-located: equal)
  float sceneScale = 1;                        // positions, near and far multiplied by this
  float colourScale = 1;                       // 16: HDR colours
  glm::vec3 background{0.02f, 0.02f, 0.05f};
};

// A method with options: one row of the atlas.
struct StressConfig {
  std::string method;
  std::map<std::string, std::string> options;
  std::string label() const;  // "wboit accum=rgba16f weight=mb7"
};

inline const std::vector<int> kStressLayers = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096};
inline const std::vector<float> kStressAlphas = {0.0f, 1e-7f, 1e-4f, 0.01f, 0.1f, 0.5f, 0.9f, 0.99f, 1.0f - 1e-6f, 1.0f};

std::vector<StressCondition> stressConditions();
// Every registered method's MethodInfo::stressVariants, in registry order.
std::vector<StressConfig> stressConfigs();

// The parametric scene: `layers` camera-facing quads covering the whole view, alternating two
// colours, submitted in a fixed shuffled order; width × height pixels.
Scene stressScene(const StressCondition& condition, int layers, float alpha, int width, int height);

// The exact composite of the scene at any pixel, in double: the layers sorted by distance (equal
// distances: the earlier submission in front, the ground truths' tie rule), OVER back to front
// onto the background.
glm::dvec3 stressExact(const Scene& scene);

struct StressCell {
  int layers = 0;
  float alpha = 0;
  double error = 0;                   // max over pixels and RGB of |result − exact| (finite pixels)
  size_t nonFinitePixels = 0;
  std::vector<std::string> infIn;     // attachments holding ±inf or NaN after the frame
  // "reveal" reached 0 although the exact Π(1 − α), rounded once into the reveal's format, is
  // not 0: the repeated multiplicative blends lost it early (reaching 0 where the format cannot
  // hold the exact value is only the format's range, and is not counted).
  bool revealUnderflow = false;
  uint64_t momentFallbacks = 0;       // MBOIT fragments whose moments could not be used
};

struct StressRow {
  StressConfig config;
  StressCondition condition;
  std::vector<StressCell> cells;  // layers-major: layers[i] × alphas[j] at i·alphas + j
};

struct StressOptions {
  std::vector<std::string> conditions, methods;  // empty: all
  std::vector<int> layers = kStressLayers;
  std::vector<float> alphas = kStressAlphas;
  int size = 4;                                  // pixels per side of each cell's image
};

using StressProgress = std::function<void(const std::string&, int, int)>;

std::vector<StressRow> runStress(const StressOptions& options, Renderer& renderer, const StressProgress& progress);
// The atlas's rows for the options, in runStress's order (conditions, then configurations), without
// their cells; an unknown condition or method fails here.
std::vector<StressRow> stressRowsFor(const StressOptions& options);
// Renders the cells of one of them.
void renderStressRow(StressRow& row, const StressOptions& options, Renderer& renderer);

// Renders one cell (exposed for the tests).
StressCell stressCell(const StressConfig& config, const StressCondition& condition, int layers, float alpha, int size,
                      Renderer& renderer);

}  // namespace oitref::tools
