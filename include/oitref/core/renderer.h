// The emulated GPU: draws triangles and full-screen passes into a Framebuffer.
//
// Stages (one source file each, in src/core/pipeline/): primitive assembly and clipping (clip.cpp),
// triangle setup (setup.cpp), binning into tiles (binning.cpp), rasterization per tile
// (raster.cpp), and per-fragment operations — interpolation, depth test, shading, blending
// (fragment_ops.cpp). Tiles are rasterized in parallel with oneTBB; each tile is owned by one
// worker and walks its triangles in submission order, so every pixel sees its fragments in
// primitive order and the result is bit-identical for any thread count. Draws run under the
// default floating-point environment (round to nearest, no flush-to-zero) whatever the calling
// thread has set.
//
// Not implemented (not needed by any OIT method here): stencil, scissor, multisampling, polygon
// offset, lines and points, geometry/tessellation stages, sRGB targets, dithering.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>

#include "oitref/core/depth.h"
#include "oitref/core/geometry.h"
#include "oitref/core/image.h"
#include "oitref/core/pipeline_state.h"
#include "oitref/core/shader.h"

namespace oitref {

// Attachments of a pass. All bound attachments must have the same size.
struct Framebuffer {
  std::array<Image*, kMaxColorTargets> color{};
  DepthBuffer* depth = nullptr;
  // Clears that the next draw (Renderer::draw, drawSequence, drawFullscreen) applies before its
  // first fragment, with its state's profile: glClearBuffer, then the draw. The same bits as
  // Image::clear and DepthBuffer::clear before the draw, but drawSequence clears a tile at a
  // time, as the worker that draws the tile begins it (llvmpipe bins a clear into each tile's
  // commands the same way), so that the tile's texels are in cache when its fragments blend
  // into them, and the threads share the clearing. The draw consumes them: a later draw with
  // this Framebuffer clears nothing.
  std::array<std::optional<glm::vec4>, kMaxColorTargets> clearColor{};
  std::optional<double> clearDepth;

  int width() const;
  int height() const;
  void validate() const;  // throws std::invalid_argument on no attachments or mismatched sizes
};

struct DrawStats {
  uint64_t trianglesSubmitted = 0;
  uint64_t trianglesRasterized = 0;  // after clipping (which may split), culling and zero-area removal
  uint64_t trianglesNonFinite = 0;   // dropped: a vertex with NaN or inf (GL leaves this undefined)
  uint64_t fragmentsRasterized = 0;  // covered pixel centres
  uint64_t fragmentsShaded = 0;      // fragment shader invocations
  uint64_t fragmentsDepthFailed = 0;
  uint64_t fragmentsDiscarded = 0;
  uint64_t fragmentsWritten = 0;     // reached blending
  double setupMs = 0, rasterMs = 0;

  DrawStats& operator+=(const DrawStats& o);
};

// The pixels of a tile: the unit of parallel work, each tile's pixels drawn by one thread.
struct TileShape {
  int width = 128, height = 32;
};

// A tile's pixels in bands of rows, with work on each band between its draws and the next band's,
// as a tiling GPU runs a tile shader on its tile memory between draws (Metal's
// dispatchThreadsPerTile): what the fragment shaders gather for a band is finished while it is in
// the worker's cache. With bands, drawSequence draws each band of a tile through all of its draws
// (every pixel still sees the draws' fragments in draw order, then primitive order), calling
// `begin` before the band's first fragment and `end` after its last, on the worker that draws it;
// [x0, x1) × [y0, y1) are the band's pixels. `begin` also gets how many triangles the draws bin
// to the band's tile: no pixel of it gets more fragments (a triangle covers a pixel centre at
// most once, and the pieces of a clipped one do not overlap). Tiles with no triangle are skipped.
struct TileRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
struct TileBands {
  int rows = 0;  // rows a band; 0: no bands (the default)
  std::function<void(const TileRect&, uint32_t triangles)> begin;
  std::function<void(const TileRect&)> end;
};

struct RendererOptions {
  int threads = 0;      // 0: every hardware thread
  // Square tiles of this many pixels, a power of two from 8 to 256; 0 (the default): wide tiles
  // chosen for the viewport (Renderer::tileShapeFor). Any size or shape, the same bits.
  int tileSize = 0;
  // Hand fragments to the fragment operations one at a time instead of as row spans with batched
  // blending: the same bits, slower; the oracle of the span path's tests.
  bool perFragment = false;
};

// A draw whose clipped triangles cannot be placed within a sub-pixel step from their fp32 clip
// coordinates (clip coordinates far beyond the guard band: a camera zoomed to a tiny fov_y, or
// geometry that far off its axis): drawSequence refuses it rather than draw rounding errors.
struct RasterPrecisionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A renderer owns its worker arena and reuses its buffers between draws; one draw at a time.
class Renderer {
 public:
  explicit Renderer(RendererOptions options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  int threads() const;
  // The tiles a draw into a width × height viewport uses.
  TileShape tileShapeFor(int width, int height) const;
  const RendererOptions& options() const { return options_; }

  DrawStats draw(Framebuffer& fb, const PipelineState& state, const Geometry& geometry, const FragmentProgram& program);
  // Several draws into one framebuffer with one state, in order: the same bits as calling draw()
  // for each (every pixel still sees the draws' fragments in draw order, then primitive order),
  // but each tile runs all of them while its attachments are in cache — as a tiling GPU or
  // llvmpipe bins a frame's draws — instead of each draw sweeping the whole framebuffer.
  // FragmentInput::drawId is each draw's drawId. Returns the draws' statistics summed.
  struct DrawCall {
    const Geometry* geometry = nullptr;
    FragmentProgram program;
    uint32_t drawId = 0;
  };
  DrawStats drawSequence(Framebuffer& fb, const PipelineState& state, const std::vector<DrawCall>& draws,
                         const TileBands& bands = {});
  // One fragment per pixel of the viewport, at window depth 0, with no attributes, through the
  // same fragment operations (depth test if enabled, blending, write masks).
  DrawStats drawFullscreen(Framebuffer& fb, const PipelineState& state, const FragmentProgram& program);
  // body(i) for i in [0, n) on this renderer's workers (and no others), each under the default
  // floating-point environment: for work beside the pipeline, such as the ray cast.
  void parallelFor(size_t n, const std::function<void(size_t)>& body);

 private:
  RendererOptions options_;
  struct Arena;
  std::unique_ptr<Arena> arena_;
};

}  // namespace oitref
