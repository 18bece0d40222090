// Stage 3: binning — which triangles touch which tile, in submission order.
//
// The viewport is cut into square tiles. Setup runs over fixed-size chunks of input triangles in
// parallel; binning is a counting sort (count per chunk and tile, prefix sums in (tile, chunk)
// order, scatter), so each tile's list holds its triangles in exactly the order they were
// submitted, whatever the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "pipeline/setup.h"

namespace oitref::detail {

struct TileGrid {
  int tileSize = 64;
  int x0 = 0, y0 = 0, width = 0, height = 0;  // the viewport
  int tilesX = 0, tilesY = 0;

  TileGrid(int tileSize, int x0, int y0, int width, int height);
  int count() const { return tilesX * tilesY; }
  PixelRect tileRect(int tile) const;
};

struct BinnedTriangles {
  std::vector<SetupTriangle> triangles;        // all set-up triangles, in submission order
  std::vector<ClipBarycentrics> clipBarycentrics;
  std::vector<uint32_t> tileStart;             // count()+1 offsets into tileTriangles
  std::vector<uint32_t> tileTriangles;         // triangle indices, per tile in submission order
  SetupCounters counters;
};

// Runs setup over every triangle of `geometry` and bins the results. `parallelFor(n, body)`
// must call body(i) once for each i in [0, n), in any order on any thread.
template <typename ParallelFor>
BinnedTriangles setupAndBin(const Geometry& geometry, const SetupContext& context, const TileGrid& grid,
                            ParallelFor&& parallelFor);

// Chunk size for setup: fixed, so the work split never depends on the thread count.
inline constexpr size_t kSetupChunk = 8192;

// Implementation pieces (binning.cpp).
struct SetupChunk {
  std::vector<SetupTriangle> triangles;
  std::vector<ClipBarycentrics> clipBarycentrics;
  std::vector<uint32_t> tileCounts;
  SetupCounters counters;
};
void setupChunk(const Geometry& geometry, const SetupContext& context, const TileGrid& grid, size_t chunk,
                SetupChunk& out);
void layoutBins(std::vector<SetupChunk>& chunks, const TileGrid& grid, BinnedTriangles& out,
                std::vector<uint32_t>& chunkTriangleOffset, std::vector<uint32_t>& chunkClipOffset,
                std::vector<uint32_t>& cursor);
void scatterChunk(SetupChunk& chunk, size_t chunkIndex, const TileGrid& grid, uint32_t triangleOffset,
                  uint32_t clipOffset, std::vector<uint32_t>& cursor, BinnedTriangles& out);

template <typename ParallelFor>
BinnedTriangles setupAndBin(const Geometry& geometry, const SetupContext& context, const TileGrid& grid,
                            ParallelFor&& parallelFor) {
  const size_t chunkCount = (geometry.triangleCount() + kSetupChunk - 1) / kSetupChunk;
  std::vector<SetupChunk> chunks(chunkCount);
  parallelFor(chunkCount, [&](size_t c) { setupChunk(geometry, context, grid, c, chunks[c]); });
  BinnedTriangles out;
  std::vector<uint32_t> triangleOffset, clipOffset, cursor;
  layoutBins(chunks, grid, out, triangleOffset, clipOffset, cursor);
  parallelFor(chunkCount, [&](size_t c) {
    scatterChunk(chunks[c], c, grid, triangleOffset[c], clipOffset[c], cursor, out);
  });
  return out;
}

}  // namespace oitref::detail
