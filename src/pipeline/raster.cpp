#include "pipeline/raster.h"

#include <algorithm>

namespace oitref::detail {

constexpr int kMinSpan = 4;

void rasterizeTile(const BinnedTriangles& bins, int tile, const PixelRect& r, int subpixelBits, bool perFragment,
                   FragmentStage& stage) {
  const int64_t S = int64_t(1) << subpixelBits;
  for (uint32_t k = bins.tileStart[size_t(tile)]; k < bins.tileStart[size_t(tile) + 1]; ++k) {
    const uint32_t id = bins.tileTriangles[k];
    const SetupTriangle& t = bins.triangle(id);
    const int x0 = std::max(r.x0, t.bounds.x0), x1 = std::min(r.x1, t.bounds.x1);
    const int y0 = std::max(r.y0, t.bounds.y0), y1 = std::min(r.y1, t.bounds.y1);
    if (x0 >= x1 || y0 >= y1) continue;
    bool begun = false;
    // An exclusive edge needs E > 0, i.e. E − 1 ≥ 0: `bias` folds the fill rule into one sign test.
    int64_t bias[3], stepX[3], rowStart[3];
    const int64_t px = int64_t(x0) * S + S / 2, py = int64_t(y0) * S + S / 2;
    for (int i = 0; i < 3; ++i) {
      bias[i] = (t.inclusiveEdges >> i) & 1 ? 0 : 1;
      stepX[i] = t.edgeA[i] * S;
      rowStart[i] = t.edgeA[i] * px + t.edgeB[i] * py + t.edgeC[i];
    }
    auto covered = [&](const int64_t* e) { return ((e[0] - bias[0]) | (e[1] - bias[1]) | (e[2] - bias[2])) >= 0; };
    for (int y = y0; y < y1; ++y) {
      int64_t e[3] = {rowStart[0], rowStart[1], rowStart[2]};
      // The row's runs of covered pixels, each handed over whole (one per row: the coverage of a
      // triangle is convex, but nothing here relies on it).
      for (int x = x0; x < x1;) {
        while (x < x1 && !covered(e)) ++x, e[0] += stepX[0], e[1] += stepX[1], e[2] += stepX[2];
        const int runStart = x;
        while (x < x1 && covered(e)) ++x, e[0] += stepX[0], e[1] += stepX[1], e[2] += stepX[2];
        if (x == runStart) break;
        if (!begun) {
          stage.beginTriangle(t);
          begun = true;
        }
        // Runs shorter than kMinSpan (small triangles) cost less one fragment at a time.
        if (perFragment || x - runStart < kMinSpan)
          for (int px = runStart; px < x; ++px) stage.fragment(px, y);
        else
          stage.span(y, runStart, x);
      }
      for (int i = 0; i < 3; ++i) rowStart[i] += t.edgeB[i] * S;
    }
  }
}

}  // namespace oitref::detail
