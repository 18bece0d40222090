// Stage 4: rasterization of one tile. Walks the tile's triangles in submission order; for each
// row of its bounding box inside the tile, the covered pixel centres are those where all three
// edge functions (exact int64) pass the fill rule; each edge bounds them on one side, found by
// exact integer division, so a row's coverage is one run, handed to the fragment stage
// (FragmentStage::span; short runs and, with `perFragment`, every pixel one fragment() call
// each, the oracle of the span path's tests). The coverage rule is in setup.h.
#pragma once

#include "pipeline/binning.h"
#include "pipeline/fragment_ops.h"

namespace oitref::detail {

void rasterizeTile(const BinnedTriangles& bins, int tile, const PixelRect& tileRect, int subpixelBits, bool perFragment,
                   FragmentStage& stage);

}  // namespace oitref::detail
