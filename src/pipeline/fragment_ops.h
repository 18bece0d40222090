// Stage 5: per-fragment operations, in the order of GL 4.6 chapters 14.9, 15 and 17:
// attribute interpolation → (early) depth test → fragment shader → (late) depth test →
// depth write → blending and colour write for each output the shader wrote.
//
// Interpolation (GL 4.6 §14.6.1 eq. 14.9, 14.10), all in double at the pixel centre:
//   λ_i = E_i / area2                    window-space barycentrics (exact integers E_i)
//   z   = Σ λ_i z_i                      depth: linear in window space
//   b_i = (λ_i / w_i) / Σ_j (λ_j / w_j)  perspective-correct barycentrics
//   a   = Σ b_i a_i                      each attribute, then rounded once to fp32
// For a clipped triangle a_i are themselves Σ_k β_ik · a(original vertex k), evaluated in double.
#pragma once

#include <cstdint>
#include <vector>

#include "blend/target_blender.h"
#include "oitref/renderer.h"
#include "pipeline/setup.h"

namespace oitref::detail {

struct FragmentCounters {
  uint64_t rasterized = 0, shaded = 0, depthFailed = 0, discarded = 0, written = 0;
};

class FragmentStage {
 public:
  FragmentStage(Framebuffer& fb, const PipelineState& state, const FragmentProgram& program, const Geometry* geometry);

  // Prepares the triangle's per-vertex attributes (double) before its fragments arrive;
  // `clipBarycentrics` is the array its clipSlot refers to.
  void beginTriangle(const SetupTriangle& triangle, const std::vector<ClipBarycentrics>& clipBarycentrics);
  // A covered pixel centre with its (unbiased) edge-function values.
  void fragment(int x, int y, const int64_t e[3]);
  // A full-screen pass pixel: window depth 0, no attributes.
  void fullscreenPixel(int x, int y);

  const FragmentCounters& counters() const { return counters_; }

 private:
  void process(FragmentInput& in, double z, const double* perspectiveBary);
  void interpolateAttributes(const double* b);

  Framebuffer& fb_;
  const PipelineState& state_;
  const FragmentProgram& program_;
  const Geometry* geometry_;
  const SetupTriangle* triangle_ = nullptr;
  bool earlyTests_;
  unsigned boundTargets_ = 0;
  std::vector<TargetBlender> blenders_;  // per bound target, in target order
  std::vector<double> vertexAttributes_;  // 3 × attributeCount
  std::vector<float> attributes_;         // interpolated, for the shader
  FragmentOutput output_;
  FragmentCounters counters_;
};

}  // namespace oitref::detail
