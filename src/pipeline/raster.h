// Stage 4: rasterization of one tile. Walks the tile's triangles in submission order; for each,
// visits the pixel centres of its bounding box inside the tile, evaluates the three edge
// functions incrementally (exact int64 additions) and hands each row's runs of covered samples
// to the fragment stage (FragmentStage::span; with `perFragment`, one fragment() call each, the
// oracle of the span path's tests). The coverage rule is in setup.h.
#pragma once

#include "pipeline/binning.h"
#include "pipeline/fragment_ops.h"

namespace oitref::detail {

void rasterizeTile(const BinnedTriangles& bins, int tile, const PixelRect& tileRect, int subpixelBits, bool perFragment,
                   FragmentStage& stage);

}  // namespace oitref::detail
