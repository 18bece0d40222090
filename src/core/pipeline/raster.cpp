#include "pipeline/raster.h"

#include <algorithm>

namespace oitref::detail {
namespace {

constexpr int kMinSpan = 4;
constexpr uint32_t kAhead = 8;

}  // namespace

void rasterizeTile(const BinnedTriangles& bins, int tile, const PixelRect& r, int subpixelBits, bool perFragment,
                   FragmentStage& stage) {
  const int64_t S = int64_t(1) << subpixelBits;
  const uint32_t first = bins.tileStart[size_t(tile)], end = bins.tileStart[size_t(tile) + 1];
  for (uint32_t k = first; k < end; ++k) {
    // A tile's triangles lie far apart among all of the draw's (each tile takes a few of many
    // small ones), too far for the hardware to guess: ask for the set-up triangle kAhead ahead,
    // and for the vertices of the one half-way there, whose record has arrived by now.
    if (k + kAhead < end) {
      const char* ahead = reinterpret_cast<const char*>(&bins.triangle(bins.tileTriangles[k + kAhead]));
      for (size_t b = 0; b < sizeof(SetupTriangle); b += 64) __builtin_prefetch(ahead + b);
    }
    if (k + kAhead / 2 < end) stage.prefetchVertices(bins.triangle(bins.tileTriangles[k + kAhead / 2]));
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
    for (int y = y0; y < y1; ++y) {
      // The row's covered pixels, from the three half-planes at once: edge i covers x0 + k where
      // rowStart + k·stepX − bias ≥ 0, a bound on k by exact integer division (the same pixels as
      // testing each one). Their intersection is one run: a triangle's coverage of a row is convex.
      int64_t lo = 0, hi = int64_t(x1 - x0);  // k in [lo, hi)
      for (int i = 0; i < 3 && lo < hi; ++i) {
        const int64_t e = rowStart[i] - bias[i], step = stepX[i];
        if (step > 0) lo = std::max(lo, ceilDiv(-e, step));
        else if (step < 0) hi = std::min(hi, floorDiv(e, -step) + 1);
        else if (e < 0) hi = lo;
      }
      if (lo < hi) {
        const int runStart = x0 + int(lo), runEnd = x0 + int(hi);
        if (!begun) {
          stage.beginTriangle(t, bins.planes(id));
          begun = true;
        }
        // Runs shorter than kMinSpan (small triangles) cost less one fragment at a time.
        if (perFragment || runEnd - runStart < kMinSpan)
          for (int px = runStart; px < runEnd; ++px) stage.fragment(px, y);
        else
          stage.span(y, runStart, runEnd);
      }
      for (int i = 0; i < 3; ++i) rowStart[i] += t.edgeB[i] * S;
    }
  }
}

}  // namespace oitref::detail
