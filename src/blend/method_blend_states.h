// The blend states oitref's methods draw with, named once: the methods take them from here
// (methods/method_common.cpp, dualpeel.cpp, meshkin3.cpp), their GL mirrors through the methods,
// and the profile blend models instantiate a kernel specialised for each (kMethodBlendStates), as
// llvmpipe compiles a blend function per state. Any other state takes the general kernel, with the
// same bits.
#pragma once

#include "oitref/blend_state.h"

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

inline constexpr BlendState kMethodBlendStates[] = {kOver,      kAdditive, kRevealage, kProduct, kSingleTargetWeighted,
                                                    kComposite, kUnder,    kPremultipliedOntoBackground, kMax};

}  // namespace oitref::detail::states
