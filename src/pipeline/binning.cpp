#include "pipeline/binning.h"

#include <algorithm>
#include <cstring>

namespace oitref::detail {
namespace {

struct TileRange {
  int tx0, ty0, tx1, ty1;  // inclusive-exclusive
};

TileRange tilesTouched(const PixelRect& r, const TileGrid& g) {
  return {(r.x0 - g.x0) / g.tileSize, (r.y0 - g.y0) / g.tileSize, (r.x1 - 1 - g.x0) / g.tileSize + 1,
          (r.y1 - 1 - g.y0) / g.tileSize + 1};
}

}  // namespace

TileGrid::TileGrid(int tileSize_, int x0_, int y0_, int width_, int height_)
    : tileSize(tileSize_), x0(x0_), y0(y0_), width(width_), height(height_),
      tilesX((width_ + tileSize_ - 1) / tileSize_), tilesY((height_ + tileSize_ - 1) / tileSize_) {}

PixelRect TileGrid::tileRect(int tile) const {
  const int tx = tile % tilesX, ty = tile / tilesX;
  const int x = x0 + tx * tileSize, y = y0 + ty * tileSize;
  return {x, y, std::min(x + tileSize, x0 + width), std::min(y + tileSize, y0 + height)};
}

void setupChunk(const Geometry& geometry, const SetupContext& context, const TileGrid& grid, size_t chunk,
                SetupChunk& out) {
  const size_t begin = chunk * kSetupChunk;
  const size_t end = std::min(begin + kSetupChunk, geometry.triangleCount());
  out.triangles.reserve(end - begin);
  for (size_t t = begin; t < end; ++t)
    setupPrimitive(geometry, t, context, out.triangles, out.clipBarycentrics, out.counters);
  out.tileCounts.assign(size_t(grid.count()), 0);
  for (const SetupTriangle& tri : out.triangles) {
    const TileRange r = tilesTouched(tri.bounds, grid);
    for (int ty = r.ty0; ty < r.ty1; ++ty)
      for (int tx = r.tx0; tx < r.tx1; ++tx) ++out.tileCounts[size_t(ty) * grid.tilesX + tx];
  }
}

void layoutBins(std::vector<SetupChunk>& chunks, const TileGrid& grid, BinnedTriangles& out,
                std::vector<uint32_t>& chunkTriangleOffset, std::vector<uint32_t>& chunkClipOffset,
                std::vector<uint32_t>& cursor) {
  const size_t tiles = size_t(grid.count());
  chunkTriangleOffset.resize(chunks.size());
  chunkClipOffset.resize(chunks.size());
  uint32_t triangles = 0, clips = 0;
  for (size_t c = 0; c < chunks.size(); ++c) {
    chunkTriangleOffset[c] = triangles;
    chunkClipOffset[c] = clips;
    triangles += uint32_t(chunks[c].triangles.size());
    clips += uint32_t(chunks[c].clipBarycentrics.size());
    out.counters.rasterized += chunks[c].counters.rasterized;
    out.counters.nonFinite += chunks[c].counters.nonFinite;
  }
  out.triangles.resize(triangles);
  out.clipBarycentrics.resize(clips);
  // Prefix sums in (tile, chunk) order: cursor[c·tiles + tile] is where chunk c writes into tile.
  cursor.resize(chunks.size() * tiles);
  out.tileStart.assign(tiles + 1, 0);
  uint32_t offset = 0;
  for (size_t tile = 0; tile < tiles; ++tile) {
    out.tileStart[tile] = offset;
    for (size_t c = 0; c < chunks.size(); ++c) {
      cursor[c * tiles + tile] = offset;
      offset += chunks[c].tileCounts[tile];
    }
  }
  out.tileStart[tiles] = offset;
  out.tileTriangles.resize(offset);
}

void scatterChunk(SetupChunk& chunk, size_t chunkIndex, const TileGrid& grid, uint32_t triangleOffset,
                  uint32_t clipOffset, std::vector<uint32_t>& cursor, BinnedTriangles& out) {
  const size_t tiles = size_t(grid.count());
  uint32_t* myCursor = cursor.data() + chunkIndex * tiles;
  for (size_t i = 0; i < chunk.triangles.size(); ++i) {
    SetupTriangle& tri = chunk.triangles[i];
    if (tri.clipSlot >= 0) tri.clipSlot += int32_t(clipOffset);
    const uint32_t index = triangleOffset + uint32_t(i);
    out.triangles[index] = tri;
    const TileRange r = tilesTouched(tri.bounds, grid);
    for (int ty = r.ty0; ty < r.ty1; ++ty)
      for (int tx = r.tx0; tx < r.tx1; ++tx) out.tileTriangles[myCursor[size_t(ty) * grid.tilesX + tx]++] = index;
  }
  if (!chunk.clipBarycentrics.empty())
    std::memcpy(out.clipBarycentrics.data() + clipOffset, chunk.clipBarycentrics.data(),
                chunk.clipBarycentrics.size() * sizeof(ClipBarycentrics));
  chunk = SetupChunk{};  // release memory early
}

}  // namespace oitref::detail
