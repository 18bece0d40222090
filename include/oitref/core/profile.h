// Profiles: named sets of conversion and blending choices, so oitref can reproduce a specific
// implementation where the specifications leave a choice (see docs/rules.md).
//
//  exact     every conversion rounds to nearest, ties to even, from the exact value; UNORM
//            blending in fp32 as GL 4.6 §17.3.6 writes it. The reference default.
//  llvmpipe  Mesa's software GL driver: fp16 and F11/F10 stores round toward zero (finite
//            overflow -> largest finite value); UNORM conversion rounds the fp32 product
//            f·(2^b−1); UNORM targets blend in integers of 8 bits (r8, rg8, rgba8) or 16 bits
//            (rgb10a2) on the quantised source, a·b/(2^w−1) as lp_build_mul_norm computes it
//            (mulUnormInteger, src/core/blend/blend_unorm_integer.h); rgb10a2 channels go through
//            16 bits even with blending off and are narrowed by truncation (colour) — see src/core/format/unorm_rescale.h.
//            Float targets blend as llvmpipe's generated code does (constant folding, lerps,
//            minps/maxps; src/core/blend/blend_llvmpipe_float.h), with the lerp's multiply-add fused
//            as on CPUs with FMA (fma=on; use "llvmpipe,fma=off" for a CPU without FMA).
//            Texture filters in 8 bits (RGBA8: 8-bit weights, lerps of 8-bit values).
//            Rasterization as llvmpipe's (raster=llvmpipe): the draw module's fp32 clipper and
//            viewport, its snapping and fill rule, fp32 plane equations for depth and attributes,
//            d16/d24 depth from the fp32 product (src/core/pipeline/llvmpipe_setup.h). The shaders'
//            log and exp as gallivm's polynomials (math=llvmpipe; oitref/core/shader_builtins.h).
//  nvidia    an NVIDIA Hopper GPU (H100/H200, driver 580), measured on 233,266 recorded blend
//            cases (docs/rules.md, "Profile nvidia"; src/core/blend/blend_nvidia.h): fp16 and F11/F10
//            stores round toward zero; UNORM conversion in fixed point with b + 4 fraction bits;
//            UNORM targets blend exactly on b-bit codes (10 bits for every rgb10a2 channel);
//            float targets blend with their own precision p (24, or 11 for fp16 and r11g11b10f,
//            whose sources and constants are first stored as fp16) in a two-product adder that
//            rounds each product to odd at p + 4 bits below the larger exponent estimate.
//            Texture filters with 8-bit weights over texels widened to 16 bits (RGBA8).
//            Coverage as the GPU's: 8 sub-pixel bits, left and bottom edges (fill=bottom_left);
//            depth and attributes interpolated in double from the snapped vertices
//            (raster=nvidia); the GPU's own rounding after that is not modelled.
//
// A profile string may override single fields: "exact,fp16=rtz", "llvmpipe,unorm=exact".
// Keys: fp16, packed (F11/F10), minifloat (user minifloat formats): rne|rtz;
// unorm: exact|fp32|nvidia; unorm_blend: float|integer|nvidia; float_blend: ieee|llvmpipe|nvidia;
// fma: on|off; texture: exact|llvmpipe|nvidia (the texture filter's weights, docs/nvidia.md);
// raster: exact|llvmpipe|nvidia (clipping, snapping, coverage, interpolation, depth conversion);
// math: exact|llvmpipe (the shaders' log and exp); fill: state|bottom_left (edge coverage).
#pragma once

#include <string>

#include "oitref/core/minifloat.h"
#include "oitref/core/texture.h"
#include "oitref/core/unorm.h"

namespace oitref {

enum class UnormBlend : uint8_t { Float, Integer, Nvidia };
enum class FloatBlend : uint8_t { Ieee, Llvmpipe, Nvidia };
// How the pipeline before the fragment shader computes: Exact interpolates each fragment from the
// original triangle in double (src/core/pipeline/fragment_ops.h); Llvmpipe is Mesa 22.3.6's
// arithmetic, fp32 from the clipper to the depth buffer (src/core/pipeline/llvmpipe_setup.h);
// Nvidia is Exact's arithmetic from the vertices as the GPU snapped them (src/core/pipeline/setup.cpp).
enum class Rasterization : uint8_t { Exact, Llvmpipe, Nvidia };
// The GLSL builtins the methods' shaders call where GLSL leaves their precision open (log, exp):
// Exact rounds the exact value once (the methods' det_math.h, in double); Llvmpipe is gallivm's
// fp32 polynomials (oitref/core/shader_builtins.h), the shader's surrounding arithmetic in fp32.
enum class ShaderMath : uint8_t { Exact, Llvmpipe };
// Which samples on a triangle's edge it covers, a choice GL leaves to the implementation
// (GL 4.6 §14.6.1): State takes PipelineState::raster (fill convention and sub-pixel bits) as
// set; BottomLeft snaps to 8 sub-pixel bits and takes left and bottom edges in GL's window
// coordinates whatever the state, as llvmpipe does in a framebuffer object (lp_setup_tri.c) and
// as an NVIDIA Hopper GPU was measured to (docs/nvidia.md, "Coverage, depth and interpolation").
enum class FillRule : uint8_t { State, BottomLeft };

struct Profile {
  std::string name = "exact";
  Rounding fp16 = Rounding::NearestEven;
  Rounding packedFloat = Rounding::NearestEven;  // the F11/F10 channels of r11g11b10f
  Rounding minifloat = Rounding::NearestEven;    // user-defined minifloat formats
  UnormRounding unorm = UnormRounding::ExactNearestEven;
  UnormBlend unormBlend = UnormBlend::Float;
  FloatBlend floatBlend = FloatBlend::Ieee;  // how float targets evaluate the blend equation
  bool fma = false;                          // llvmpipe's lerp fused (CPUs with FMA) or not
  TextureFiltering texture = TextureFiltering::Exact;  // texture filters' arithmetic (oitref/core/texture.h)
  Rasterization raster = Rasterization::Exact;
  ShaderMath math = ShaderMath::Exact;
  FillRule fill = FillRule::State;

  bool operator==(const Profile&) const = default;
  std::string describe() const;  // every field, e.g. for reports and failing tests
};

Profile exactProfile();
Profile llvmpipeProfile();
Profile nvidiaProfile();
// "exact", "llvmpipe", "nvidia", optionally followed by ",key=value" overrides. Throws
// std::invalid_argument naming the bad part and the valid choices.
Profile parseProfile(const std::string& text);

}  // namespace oitref
