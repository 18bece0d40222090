// Stage 4: rasterization of one tile. Walks the tile's triangles in submission order; for each,
// visits the pixel centres of its bounding box inside the tile, evaluates the three edge
// functions incrementally (exact int64 additions) and hands covered samples to the fragment
// stage. The coverage rule is in setup.h.
#pragma once

#include "pipeline/binning.h"
#include "pipeline/fragment_ops.h"

namespace oitref::detail {

void rasterizeTile(const BinnedTriangles& bins, int tile, const PixelRect& tileRect, int subpixelBits,
                   FragmentStage& stage);

}  // namespace oitref::detail
