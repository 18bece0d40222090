#include "pipeline/binning.h"

#include <algorithm>

namespace oitref::detail {
namespace {

struct TileRange {
  int tx0, ty0, tx1, ty1;  // inclusive-exclusive
};

TileRange tilesTouched(const PixelRect& r, const TileGrid& g) {
  return {(r.x0 - g.x0) / g.tileWidth, (r.y0 - g.y0) / g.tileHeight, (r.x1 - 1 - g.x0) / g.tileWidth + 1,
          (r.y1 - 1 - g.y0) / g.tileHeight + 1};
}

}  // namespace

TileGrid::TileGrid(int tileWidth_, int tileHeight_, int x0_, int y0_, int width_, int height_)
    : tileWidth(tileWidth_), tileHeight(tileHeight_), x0(x0_), y0(y0_), width(width_), height(height_),
      tilesX((width_ + tileWidth_ - 1) / tileWidth_), tilesY((height_ + tileHeight_ - 1) / tileHeight_) {}

PixelRect TileGrid::tileRect(int tile) const {
  const int tx = tile % tilesX, ty = tile / tilesX;
  const int x = x0 + tx * tileWidth, y = y0 + ty * tileHeight;
  return {x, y, std::min(x + tileWidth, x0 + width), std::min(y + tileHeight, y0 + height)};
}

void setupChunk(const Geometry& geometry, const SetupContext& context, const TileGrid& grid, size_t chunk,
                SetupChunk& out) {
  const size_t begin = chunk * kSetupChunk;
  const size_t end = std::min(begin + kSetupChunk, geometry.triangleCount());
  out.triangles.clear();
  out.counters = {};
  out.triangles.reserve(end - begin);
  out.planes.clear();
  if (context.rule == Rasterization::Llvmpipe)
    for (size_t t = begin; t < end; ++t) setupPrimitiveLlvmpipe(geometry, t, context, out.triangles, out.planes, out.counters);
  else
    for (size_t t = begin; t < end; ++t) setupPrimitive(geometry, t, context, out.triangles, out.counters);
  out.tileCounts.assign(size_t(grid.count()), 0);
  for (const SetupTriangle& tri : out.triangles) {
    const TileRange r = tilesTouched(tri.bounds, grid);
    for (int ty = r.ty0; ty < r.ty1; ++ty)
      for (int tx = r.tx0; tx < r.tx1; ++tx) ++out.tileCounts[size_t(ty) * grid.tilesX + tx];
  }
}

void layoutBins(const TileGrid& grid, BinnedTriangles& bins) {
  const size_t tiles = size_t(grid.count()), chunks = bins.chunks.size();
  bins.counters = {};
  for (const SetupChunk& c : bins.chunks) {
    bins.counters.rasterized += c.counters.rasterized;
    bins.counters.nonFinite += c.counters.nonFinite;
    bins.counters.clipErrorPixels = std::max(bins.counters.clipErrorPixels, c.counters.clipErrorPixels);
  }
  // Prefix sums in (tile, chunk) order: cursor[c·tiles + tile] is where chunk c writes into tile.
  bins.cursor.resize(chunks * tiles);
  bins.tileStart.assign(tiles + 1, 0);
  uint32_t offset = 0;
  for (size_t tile = 0; tile < tiles; ++tile) {
    bins.tileStart[tile] = offset;
    for (size_t c = 0; c < chunks; ++c) {
      bins.cursor[c * tiles + tile] = offset;
      offset += bins.chunks[c].tileCounts[tile];
    }
  }
  bins.tileStart[tiles] = offset;
  bins.tileTriangles.resize(offset);
}

void scatterChunk(size_t chunk, const TileGrid& grid, BinnedTriangles& bins) {
  const size_t tiles = size_t(grid.count());
  uint32_t* cursor = bins.cursor.data() + chunk * tiles;
  const std::vector<SetupTriangle>& triangles = bins.chunks[chunk].triangles;
  for (size_t i = 0; i < triangles.size(); ++i) {
    const uint32_t id = uint32_t(chunk << 16) | uint32_t(i);
    const TileRange r = tilesTouched(triangles[i].bounds, grid);
    for (int ty = r.ty0; ty < r.ty1; ++ty)
      for (int tx = r.tx0; tx < r.tx1; ++tx) bins.tileTriangles[cursor[size_t(ty) * grid.tilesX + tx]++] = id;
  }
}

}  // namespace oitref::detail
