// The blend states oitref's methods draw with, named once: the methods take them from here
// (methods/method_common.cpp, dualpeel.cpp, meshkin3.cpp), their GL mirrors through the methods,
// and the profile blend models instantiate a kernel specialised for each (kMethodBlendStates), as
// llvmpipe compiles a blend function per state. Any other state takes the general kernel, with the
// same bits.
#pragma once

#include <iterator>

#include "oitref/core/blend_state.h"

namespace oitref::detail::states {

using E = BlendEquation;
using F = BlendFactor;

// OVER: src_alpha, one_minus_src_alpha; alpha one, one_minus_src_alpha.
inline constexpr BlendState kOver = BlendState::separate(E::Add, E::Add, F::SrcAlpha, F::OneMinusSrcAlpha, F::One, F::OneMinusSrcAlpha);
// Σ: one, one.
inline constexpr BlendState kAdditive = BlendState::same(E::Add, F::One, F::One);
// Π(1 − α): zero, one_minus_src_color.
inline constexpr BlendState kRevealage = BlendState::same(E::Add, F::Zero, F::OneMinusSrcColor);
// Π c (Meshkin's product term): zero, src_color.
inline constexpr BlendState kProduct = BlendState::same(E::Add, F::Zero, F::SrcColor);
// McGuire–Bavoil listing 4: RGB one, one; alpha zero, one_minus_src_alpha.
inline constexpr BlendState kSingleTargetWeighted = BlendState::separate(E::Add, E::Add, F::One, F::One, F::Zero, F::OneMinusSrcAlpha);
// C_s·(1 − α_s) + C_d·α_s, alpha kept.
inline constexpr BlendState kComposite = BlendState::separate(E::Add, E::Add, F::OneMinusSrcAlpha, F::SrcAlpha, F::Zero, F::One);
// Front-to-back "under": dst_alpha, one; zero, one_minus_src_alpha.
inline constexpr BlendState kUnder = BlendState::separate(E::Add, E::Add, F::DstAlpha, F::One, F::Zero, F::OneMinusSrcAlpha);
// Premultiplied layers onto the background: one, src_alpha; zero, one.
inline constexpr BlendState kPremultipliedOntoBackground = BlendState::separate(E::Add, E::Add, F::One, F::SrcAlpha, F::Zero, F::One);
// MAX of source and destination (dual depth peeling's depth range).
inline constexpr BlendState kMax = BlendState::same(E::Max, F::One, F::One);
// A premultiplied front layer over the background: C_s + C_d·(1 − α_s), alpha kept (dual peeling's merge).
inline constexpr BlendState kFrontOntoBackground = BlendState::separate(E::Add, E::Add, F::One, F::OneMinusSrcAlpha, F::Zero, F::One);

inline constexpr BlendState kMethodBlendStates[] = {kOver,      kAdditive, kRevealage, kProduct, kSingleTargetWeighted,
                                                    kComposite, kUnder,    kPremultipliedOntoBackground, kMax,
                                                    kFrontOntoBackground};

// The float layouts each state above is drawn into by a method — a bit per channel count: r (1),
// rg (2), rgba (4) — for the kernels compiled once per state and layout (blend_llvmpipe_float.cpp:
// each costs compile time, and the unused ones were most of it). A pair not listed blends through
// the general kernel: the same bits, slower. (The methods' attachments decide these: R32F/R16F
// Σ and Π(1 − α) targets, RG32F depth ranges, RGBA everything else.)
inline constexpr unsigned kR = 1, kRg = 2, kRgba = 4;
inline constexpr unsigned kMethodFloatLayouts[] = {kRgba, kR | kRg | kRgba, kR,    kRgba,      kRgba,
                                                   kRgba, kRgba,             kRgba, kRg | kRgba, kRgba};
static_assert(std::size(kMethodFloatLayouts) == std::size(kMethodBlendStates));

}  // namespace oitref::detail::states
