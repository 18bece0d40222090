// Stage 3: binning — which triangles touch which tile, in submission order.
//
// The viewport is cut into tiles (Renderer::tileShapeFor). Setup runs over fixed-size chunks of
// input triangles in parallel (the split never depends on the thread count); each chunk keeps its
// own set-up triangles, named by (chunk << 16 | index in chunk). Binning is a counting sort: count
// per chunk and tile, prefix sums in (tile, chunk) order, scatter — so each tile's list holds its
// triangles in exactly the order they were submitted, whatever the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "pipeline/llvmpipe_setup.h"
#include "pipeline/setup.h"

namespace oitref::detail {

// 4096 input triangles a chunk; clipping makes at most 14 of one, so a chunk holds < 2^16.
inline constexpr size_t kSetupChunk = 4096;
inline constexpr size_t kMaxTriangles = size_t(1) << 28;  // 2^16 chunks

struct TileGrid {
  int tileWidth = 128, tileHeight = 32;
  int x0 = 0, y0 = 0, width = 0, height = 0;  // the viewport
  int tilesX = 0, tilesY = 0;

  TileGrid(int tileWidth, int tileHeight, int x0, int y0, int width, int height);
  int count() const { return tilesX * tilesY; }
  PixelRect tileRect(int tile) const;
};

struct SetupChunk {
  std::vector<SetupTriangle> triangles;
  std::vector<float> planes;  // raster=llvmpipe: each triangle's plane equations (llvmpipe_setup.h)
  std::vector<uint32_t> tileCounts;
  SetupCounters counters;
};

// Kept by the renderer between draws so its buffers are reused.
struct BinnedTriangles {
  std::vector<SetupChunk> chunks;
  std::vector<uint32_t> tileStart;      // count()+1 offsets into tileTriangles
  std::vector<uint32_t> tileTriangles;  // triangle ids, per tile in submission order
  std::vector<uint32_t> cursor;         // scratch for the scatter
  SetupCounters counters;
  int planeFloats = 0;  // per triangle in SetupChunk::planes; 0 under raster=exact

  const SetupTriangle& triangle(uint32_t id) const { return chunks[id >> 16].triangles[id & 0xffff]; }
  const float* planes(uint32_t id) const {
    return planeFloats ? chunks[id >> 16].planes.data() + size_t(id & 0xffff) * size_t(planeFloats) : nullptr;
  }
};

void setupChunk(const Geometry& geometry, const SetupContext& context, const TileGrid& grid, size_t chunk,
                SetupChunk& out);
void layoutBins(const TileGrid& grid, BinnedTriangles& bins);
void scatterChunk(size_t chunk, const TileGrid& grid, BinnedTriangles& bins);

// Runs setup over every triangle of each draw's geometry and bins the results into its bins
// (bins[d] for geometries[d]): the chunks of every draw in one parallel loop, then the scatters
// likewise. A draw of fewer than kSetupChunk triangles is one chunk, so set up draw by draw, a
// frame of many small objects ran its setup on one thread while the others waited.
// `parallelFor(n, body)` must call body(i) once for each i in [0, n), on any thread.
template <typename ParallelFor>
void setupAndBin(const std::vector<const Geometry*>& geometries, const SetupContext& context, const TileGrid& grid,
                 BinnedTriangles* bins, ParallelFor&& parallelFor) {
  struct Item {
    uint32_t draw, chunk;
  };
  std::vector<Item> items;
  for (size_t d = 0; d < geometries.size(); ++d) {
    const size_t chunkCount = (geometries[d]->triangleCount() + kSetupChunk - 1) / kSetupChunk;
    bins[d].chunks.resize(chunkCount);
    bins[d].planeFloats = context.rule == Rasterization::Llvmpipe ? llvmpipePlaneFloats(geometries[d]->attributeCount) : 0;
    for (size_t c = 0; c < chunkCount; ++c) items.push_back({uint32_t(d), uint32_t(c)});
  }
  parallelFor(items.size(), [&](size_t i) {
    const Item it = items[i];
    setupChunk(*geometries[it.draw], context, grid, it.chunk, bins[it.draw].chunks[it.chunk]);
  });
  for (size_t d = 0; d < geometries.size(); ++d) layoutBins(grid, bins[d]);
  parallelFor(items.size(), [&](size_t i) { scatterChunk(items[i].chunk, grid, bins[items[i].draw]); });
}

}  // namespace oitref::detail
