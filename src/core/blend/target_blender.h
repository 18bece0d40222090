// One colour attachment's blend and write, resolved once per draw: the blend state, the clamped
// constant, and a kernel chosen for the format. Kernels for rgba8/rg8/r8, fp16 and fp32 targets
// decode and encode without per-channel dispatch (fp16 four channels at a time with F16C); every
// other case takes the generic path. All run blendValues (blend_math.h), so they differ only in
// speed: the test "blend: fast paths give the generic path's bits" checks it.
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "blend/blend_llvmpipe_float.h"
#include "blend/blend_math.h"
#include "blend/blend_nvidia.h"
#include "blend/blend_unorm_integer.h"
#include "oitref/core/blend_state.h"
#include "oitref/core/format.h"
#include "oitref/core/profile.h"

namespace oitref::detail {

// Formats llvmpipe calls "small float": stored in fewer than 32 bits per float channel.
inline bool isSmallFloatFormat(const Format& f) {
  const ChannelEncoding e = f.encoding();
  return e == ChannelEncoding::Half || e == ChannelEncoding::PackedFloat11_10 || e == ChannelEncoding::Minifloat;
}

class TargetBlender {
 public:
  // `smallFloatTargetBound`: the draw also writes an fp16, r11g11b10f or minifloat target (the
  // llvmpipe profile then keeps denormals in the blend arithmetic, as llvmpipe does per draw).
  TargetBlender(const Format& format, const BlendState& state, const glm::vec4& constant, const Profile& profile,
                bool allowFastPath = true, bool smallFloatTargetBound = false);
  void blend(const glm::vec4& source, uint8_t* texel) const { kernel_(*this, source, texel); }
  // blend(*sources[i], texels[i]) for i in [0, n), the kernel chosen once for the batch.
  void blendBatch(const glm::vec4* const* sources, uint8_t* const* texels, int n) const {
    batchKernel_(*this, sources, texels, n);
  }
  // The same for n consecutive texels of a row from `texels` on, sources[i] into the i-th (a span
  // whose every fragment blends): no pointer per pixel, and kernels that load and store several
  // texels at once. The same bits as blendBatch.
  // Pixels whose blend cannot change their texel's bits (keptPixels) are left alone.
  void blendRun(const glm::vec4* sources, uint8_t* texels, int n) const {
    if (skipsEmptyPixels_) return blendRunKeeping(sources, texels, n);
    runKernel_(*this, sources, texels, n);
  }
  // Bit i set where blending sources[i] over the i-th of n ≤ 64 consecutive texels would leave
  // its bits as they are, known without blending. Only for the composite states
  // (compositeBlend, premultipliedOntoBackgroundBlend) and the source (+0, +0, +0, 1), what a
  // composite's shader gives a pixel that no transparent fragment reached: 0·(1 − 1) + d·1 = d
  // (composite) or 0·1 + d·1 = d (premultiplied) on RGB and 0·1 + d·1 = d on alpha, exactly, for
  // every UNORM8 code (decoded, clamped and encoded back, or llvmpipe's integer products with the
  // factors 0 and 255) and every float d that is not NaN (canonicalised), not −0 (+0 + −0 = +0)
  // and not a denormal where the profile flushes them. The `nvidia` profile's arithmetic is not
  // covered. No bit for any other state, source or target.
  uint64_t keptPixels(const glm::vec4* sources, const uint8_t* texels, int n) const;

 private:
  using Kernel = void (*)(const TargetBlender&, const glm::vec4&, uint8_t*);
  using BatchKernel = void (*)(const TargetBlender&, const glm::vec4* const*, uint8_t* const*, int);
  using RunKernel = void (*)(const TargetBlender&, const glm::vec4*, uint8_t*, int);
  template <Kernel K>
  static void batchOf(const TargetBlender& b, const glm::vec4* const* sources, uint8_t* const* texels, int n) {
    for (int i = 0; i < n; ++i) K(b, *sources[i], texels[i]);
  }
  template <Kernel K>
  static void runOf(const TargetBlender& b, const glm::vec4* sources, uint8_t* texels, int n) {
    for (int i = 0; i < n; ++i) K(b, sources[i], texels + size_t(i) * b.texelBytes_);
  }
  // A run through the batch kernel, with the pointers it takes.
  static void runThroughBatch(const TargetBlender& b, const glm::vec4* sources, uint8_t* texels, int n);
  template <Kernel K>
  void use() {
    kernel_ = K;
    batchKernel_ = batchOf<K>;
    runKernel_ = runOf<K>;
  }
  // State: kRuntimeState blends with compiled_; an index into kMethodBlendStates, with that state
  // known when the kernel is compiled (its selects fold away; the same bits).
  static constexpr int kRuntimeState = -1;
  // The rgba8/rg8/r8, fp16 and fp32 kernels (Texels: the layout, target_blender.cpp), per pixel
  // and over a batch two pixels at a time.
  template <typename Texels, int Channels, int State>
  static void fastKernel(const TargetBlender&, const glm::vec4&, uint8_t*);
  template <typename Texels, int Channels, int State>
  static void fastBatch(const TargetBlender&, const glm::vec4* const*, uint8_t* const*, int);
  template <typename Texels, int Channels, int State>
  static void fastRun(const TargetBlender&, const glm::vec4*, uint8_t*, int);
  // fastBatch's and fastRun's loop over Pixels (target_blender.cpp: pointers per pixel, or a run).
  template <typename Texels, int Channels, int State, typename Pixels>
  static void fastPixels(const TargetBlender&, const Pixels& pixels, int n);
  template <int State> static const CompiledBlend& compiledBlend(const TargetBlender& b);
  template <int State> static bool enabled(const TargetBlender& b);
  // The fast kernel for the format layout, compiled for the state when it is a method blend state.
  void useFastKernel(ChannelEncoding encoding, int channels, int stateIndex);
  static void genericKernel(const TargetBlender&, const glm::vec4&, uint8_t*);
  static void integerUnormKernel(const TargetBlender&, const glm::vec4&, uint8_t*);
  static void integerUnormBatch(const TargetBlender&, const glm::vec4* const*, uint8_t* const*, int);
  static void integerUnormRun(const TargetBlender&, const glm::vec4*, uint8_t*, int);
  static void llvmpipeFloatKernel(const TargetBlender&, const glm::vec4&, uint8_t*);
  template <int Channels, bool Half> static void llvmpipeFloatTexelKernel(const TargetBlender&, const glm::vec4&, uint8_t*);
  template <int Channels, bool Half>
  static void llvmpipeFloatTexelBatch(const TargetBlender&, const glm::vec4* const*, uint8_t* const*, int);
  template <int Channels, bool Half>
  static void llvmpipeFloatTexelRun(const TargetBlender&, const glm::vec4*, uint8_t*, int);
  template <int Channels, bool Half>
  void useLlvmpipeTexel() {
    use<llvmpipeFloatTexelKernel<Channels, Half>>();
    if (llvmpipeTexels_.scattered) {
      batchKernel_ = llvmpipeFloatTexelBatch<Channels, Half>;
      runKernel_ = llvmpipeFloatTexelRun<Channels, Half>;
    }
  }
  // blendRun where skipsEmptyPixels_: the run's pixels that keptPixels spares are skipped.
  void blendRunKeeping(const glm::vec4* sources, uint8_t* texels, int n) const;
  static void nvidiaKernel(const TargetBlender&, const glm::vec4&, uint8_t*);
  static void maskedOffKernel(const TargetBlender&, const glm::vec4&, uint8_t*) {}

  Format format_;
  BlendState state_;
  CompiledBlend compiled_;
  glm::vec4 constant_;  // clamped to [0,1] for fixed-point targets
  glm::vec4 rawConstant_;
  Profile profile_;
  unsigned mask_;
  size_t texelBytes_;
  bool flushDenormals_;
  // keptPixels's case: a composite state on an eligible target and profile (decided per draw).
  bool skipsEmptyPixels_ = false;
  bool floatFlushesDenormals_ = false;  // the llvmpipe float model flushing denormal destinations
  LlvmpipeFloatPlan llvmpipePlan_;
  LlvmpipeFloatBlendFn llvmpipeBlend_ = nullptr;
  LlvmpipeFloatTexelFns llvmpipeTexels_;
  NvidiaBlendPlan nvidiaPlan_;
  UnormIntegerPlan unormPlan_;
  UnormIntegerBlendFn unormBlend_ = nullptr;
  UnormIntegerBatchFn unormBatch_ = nullptr;
  UnormIntegerRunFn unormRun_ = nullptr;  // RGBA8 runs four pixels at a time, where there is one
  Kernel kernel_;
  BatchKernel batchKernel_;
  RunKernel runKernel_;
};

}  // namespace oitref::detail
