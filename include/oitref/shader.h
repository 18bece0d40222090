// Fragment shaders are C++ callables. A shader reads FragmentInput and writes FragmentOutput:
// any subset of the bound colour outputs, optionally the depth, or it discards.
//
// To read an earlier pass's attachment at the fragment's own pixel (texelFetch), capture the
// Image and call image.fetch(in.x, in.y). Reading an attachment that the same pass writes is a
// feedback loop (undefined in GL); oitref returns the value before this fragment's own write.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "oitref/pipeline_state.h"

namespace oitref {

struct FragmentInput {
  int x = 0, y = 0;          // pixel, window coordinates (origin lower-left)
  glm::vec2 fragCoord{};     // gl_FragCoord.xy = (x + ½, y + ½)
  float depth = 0;           // gl_FragCoord.z: window z, linear in window space
  float viewDepth = 0;       // clip w interpolated perspective-correctly (= −z_eye for a perspective camera)
  bool frontFacing = true;   // gl_FrontFacing
  uint32_t primitiveId = 0;  // gl_PrimitiveID: the triangle's index in its draw
  uint32_t drawId = 0;       // the draw's Renderer::DrawCall::drawId (0 for draw() and full-screen passes)
  const float* attributes = nullptr;  // perspective-correct interpolated attributes
  int attributeCount = 0;

  float attribute(int i) const { return attributes[i]; }
  glm::vec2 vec2At(int i) const { return {attributes[i], attributes[i + 1]}; }
  glm::vec3 vec3At(int i) const { return {attributes[i], attributes[i + 1], attributes[i + 2]}; }
  glm::vec4 vec4At(int i) const { return {attributes[i], attributes[i + 1], attributes[i + 2], attributes[i + 3]}; }
};

class FragmentOutput {
 public:
  void write(int target, const glm::vec4& color) {
    color_[target] = color;
    written_ |= 1u << target;
  }
  void discard() { discarded_ = true; }
  void setDepth(float windowZ) {  // gl_FragDepth; the program must declare writesDepth
    depth_ = windowZ;
    depthWritten_ = true;
  }

  const glm::vec4& color(int target) const { return color_[target]; }
  unsigned writtenMask() const { return written_; }
  bool discarded() const { return discarded_; }
  bool depthWritten() const { return depthWritten_; }
  float depth() const { return depth_; }
  void reset() {
    written_ = 0;
    discarded_ = false;
    depthWritten_ = false;
  }

 private:
  std::array<glm::vec4, kMaxColorTargets> color_{};
  unsigned written_ = 0;
  bool discarded_ = false;
  bool depthWritten_ = false;
  float depth_ = 0;
};

using FragmentShader = std::function<void(const FragmentInput&, FragmentOutput&)>;

// The same shader over a batch of fragments of distinct pixels: out[i] for in[i], i < count, each
// output reset beforehand. Optional, for speed (one call per batch, the per-fragment code inlined
// into the loop); it must compute exactly what `shader` computes for each fragment, which stays
// the oracle (RendererOptions::perFragment). programOf() below makes both from one callable.
using FragmentBatchShader = std::function<void(const FragmentInput* in, FragmentOutput* out, int count)>;

// A shader plus what it declares, which decides early or late depth testing (GL 4.6 §14.9.4,
// §15.2.4): a shader that neither discards nor writes depth is tested before shading; one that
// may discard or writes depth is tested after; earlyFragmentTests (GLSL
// layout(early_fragment_tests)) forces the test and the depth write before shading even then.
// Outputs the shader does not write leave their attachment unchanged for that fragment.
// A shader that declares writesDepth but does not call setDepth keeps the interpolated depth.
//
// `pure`: the shader's only effects are its outputs and discard (no image stores, atomics or
// counters). Then a fragment that fails the depth test is not shaded even where the test comes
// after the shader (a shader that may discard): its shading could change nothing, because the
// shader cannot move the fragment's depth or the buffer's. The depth write still waits for the
// shader, so the stored bits are those of the late test; only the counters tell (such fragments
// count as failing the depth test, not as shaded or discarded). GPUs reject early the same way.
struct FragmentProgram {
  FragmentShader shader;
  bool mayDiscard = false;
  bool writesDepth = false;
  bool earlyFragmentTests = false;
  FragmentBatchShader batch = {};  // optional: `shader` over a batch
  bool pure = false;
};

// A program whose per-fragment and batch shaders are the one callable
// shader(const FragmentInput&, FragmentOutput&).
template <typename Shader>
FragmentProgram programOf(Shader shader, bool mayDiscard = false, bool writesDepth = false,
                          bool earlyFragmentTests = false, bool pure = false) {
  FragmentProgram program{shader, mayDiscard, writesDepth, earlyFragmentTests, {}, pure};
  program.batch = [shader](const FragmentInput* in, FragmentOutput* out, int count) {
    for (int i = 0; i < count; ++i) shader(in[i], out[i]);
  };
  return program;
}

}  // namespace oitref
