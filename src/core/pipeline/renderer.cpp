// The draw loop: setup and binning over chunks of triangles, then all tiles in parallel.
// oneTBB stays behind this file; stages only see a parallel-for.
#include "oitref/core/renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "oitref/core/fp_environment.h"
#include "pipeline/binning.h"
#include "pipeline/fragment_ops.h"
#include "pipeline/raster.h"

namespace oitref {
namespace {

#if defined(OITREF_STD_THREADS)
// ThreadSanitizer builds (-DOITREF_SANITIZE=thread): Debian's oneTBB library is not instrumented,
// so its task hand-offs look like races to TSan. There the same bodies run on plain std::threads,
// which TSan sees completely: what is under test is the pipeline's own synchronisation (each tile
// owned by one worker), not oneTBB's.
thread_local int tlsThreads = 1;

// An exception from a body (a shader that ends its pass, as the A-buffer's count) stops the
// remaining items and is rethrown on the calling thread, as oneTBB does.
template <typename Body>
void workerParallelFor(size_t n, Body&& body) {
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  auto work = [&] {
    const DefaultFloatingPoint fp;
    try {
      for (size_t i; (i = next.fetch_add(1)) < n;) body(i);
    } catch (...) {
      next = n;
      const std::lock_guard<std::mutex> lock(failureMutex);
      if (!failure) failure = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < tlsThreads; ++t) workers.emplace_back(work);
  work();
  for (std::thread& w : workers) w.join();
  if (failure) std::rethrow_exception(failure);
}
#else
// Every task of a draw runs under the default floating-point environment (fp_environment.h):
// oneTBB copies the arena creator's settings to its workers, whatever they are.
template <typename Body>
void workerParallelFor(size_t n, Body&& body) {
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const DefaultFloatingPoint fp;
    body(i);
  });
}
#endif

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void addCounters(DrawStats& s, const detail::FragmentCounters& c) {
  s.fragmentsRasterized += c.rasterized;
  s.fragmentsShaded += c.shaded;
  s.fragmentsDepthFailed += c.depthFailed;
  s.fragmentsDiscarded += c.discarded;
  s.fragmentsWritten += c.written;
}

// A Framebuffer's clears (Framebuffer::clearColor, clearDepth), converted once for the draw that
// takes them from it.
struct PendingClears {
  std::array<std::array<uint8_t, 16>, kMaxColorTargets> texels{};
  unsigned colors = 0;  // bit t: color[t] is cleared
  bool depth = false;
  uint32_t depthValue = 0;

  bool any() const { return colors != 0 || depth; }
  void apply(Framebuffer& fb, const detail::PixelRect& r) const {
    for (unsigned t = colors; t; t &= t - 1)
      fb.color[size_t(__builtin_ctz(t))]->clearRect(r.x0, r.y0, r.x1, r.y1, texels[size_t(__builtin_ctz(t))].data());
    if (depth) fb.depth->clearRect(r.x0, r.y0, r.x1, r.y1, depthValue);
  }
  void applyEverywhere(Framebuffer& fb) const { apply(fb, {0, 0, fb.width(), fb.height()}); }
};

PendingClears takeClears(Framebuffer& fb, const Profile& profile) {
  PendingClears c;
  const DefaultFloatingPoint fp;  // the conversion's rounding, as Image::clear
  for (size_t t = 0; t < kMaxColorTargets; ++t) {
    if (!fb.clearColor[t]) continue;
    if (!fb.color[t]) throw std::invalid_argument("Framebuffer: a clear of colour target " + std::to_string(t) + ", which has no attachment");
    encodeTexel(fb.color[t]->format(), *fb.clearColor[t], profile, c.texels[t].data());
    c.colors |= 1u << t;
    fb.clearColor[t].reset();
  }
  if (fb.clearDepth) {
    if (!fb.depth) throw std::invalid_argument("Framebuffer: a depth clear without a depth attachment");
    c.depth = true;
    c.depthValue = encodeDepth(*fb.clearDepth, fb.depth->format());
    fb.clearDepth.reset();
  }
  return c;
}

detail::SetupContext makeContext(const Framebuffer& fb, const PipelineState& state) {
  const RasterState& r = state.raster;
  if (r.subpixelBits < 1 || r.subpixelBits > 8)
    throw std::invalid_argument("raster.subpixelBits must be 1..8, got " + std::to_string(r.subpixelBits));
  detail::SetupContext c;
  c.raster = r;
  c.clipNearFar = !state.depth.clamp;
  c.rule = state.profile.raster;
  c.fusedMultiplyAdd = state.profile.fma;
  if (c.rule == Rasterization::Llvmpipe || state.profile.fill == FillRule::BottomLeft) {
    // llvmpipe snaps to 8 sub-pixel bits (lp_rast.h, FIXED_ORDER) and, in a framebuffer object,
    // whose rows go up as GL's window y does, takes left and bottom edges (lp_setup_tri.c,
    // bottom_edge_rule 0; st_atom_rasterizer.c); an NVIDIA Hopper GPU covers the same pixels
    // (docs/nvidia.md). The profile decides both; llvmpipe's setup needs them whatever `fill`.
    c.raster.subpixelBits = 8;
    c.raster.fill = FillConvention::BottomLeft;
  }
  const Viewport& v = state.viewport;
  const bool whole = v.width == 0 && v.height == 0;
  c.vx = whole ? 0 : v.x;
  c.vy = whole ? 0 : v.y;
  c.vw = whole ? fb.width() : v.width;
  c.vh = whole ? fb.height() : v.height;
  if (c.vx < 0 || c.vy < 0 || c.vw < 1 || c.vh < 1 || c.vx + c.vw > fb.width() || c.vy + c.vh > fb.height())
    throw std::invalid_argument("viewport (" + std::to_string(v.x) + "," + std::to_string(v.y) + "," +
                                std::to_string(v.width) + "," + std::to_string(v.height) +
                                ") does not lie inside the framebuffer");
  return c;
}

detail::PixelRect viewportRect(const detail::SetupContext& c) { return {c.vx, c.vy, c.vx + c.vw, c.vy + c.vh}; }

}  // namespace

DrawStats& DrawStats::operator+=(const DrawStats& o) {
  trianglesSubmitted += o.trianglesSubmitted;
  trianglesRasterized += o.trianglesRasterized;
  trianglesNonFinite += o.trianglesNonFinite;
  fragmentsRasterized += o.fragmentsRasterized;
  fragmentsShaded += o.fragmentsShaded;
  fragmentsDepthFailed += o.fragmentsDepthFailed;
  fragmentsDiscarded += o.fragmentsDiscarded;
  fragmentsWritten += o.fragmentsWritten;
  setupMs += o.setupMs;
  rasterMs += o.rasterMs;
  return *this;
}

int Framebuffer::width() const {
  for (const Image* c : color)
    if (c) return c->width();
  return depth ? depth->width() : 0;
}
int Framebuffer::height() const {
  for (const Image* c : color)
    if (c) return c->height();
  return depth ? depth->height() : 0;
}

void Framebuffer::validate() const {
  const int w = width(), h = height();
  if (w == 0) throw std::invalid_argument("framebuffer has no attachments");
  for (size_t i = 0; i < color.size(); ++i)
    if (color[i] && (color[i]->width() != w || color[i]->height() != h))
      throw std::invalid_argument("colour attachment " + std::to_string(i) + " is " +
                                  std::to_string(color[i]->width()) + "x" + std::to_string(color[i]->height()) +
                                  ", the framebuffer is " + std::to_string(w) + "x" + std::to_string(h));
  if (depth && (depth->width() != w || depth->height() != h))
    throw std::invalid_argument("depth attachment size differs from the colour attachments");
}

#if defined(OITREF_STD_THREADS)
// `threads` std::threads per parallel-for (see workerParallelFor above).
struct Renderer::Arena {
  int threads;
  std::vector<detail::BinnedTriangles> bins;  // one per draw of a sequence, reused between draws
  explicit Arena(int t) : threads(t) {}
  template <typename F>
  void execute(F&& f) {
    tlsThreads = threads;
    f();
    tlsThreads = 1;
  }
};
#else
// An arena of exactly `threads` workers. oneTBB caps workers at the hardware count by default;
// asking for more (to test determinism with 8 threads on 2 cores) raises the cap while this
// renderer lives. With several such renderers alive at once, oneTBB applies the smallest cap.
struct Renderer::Arena {
  std::optional<tbb::global_control> oversubscribe;
  tbb::task_arena arena;
  std::vector<detail::BinnedTriangles> bins;  // one per draw of a sequence, reused between draws
  explicit Arena(int threads)
      : oversubscribe(threads > int(tbb::this_task_arena::max_concurrency())
                          ? std::optional<tbb::global_control>(std::in_place, tbb::global_control::max_allowed_parallelism,
                                                               size_t(threads))
                          : std::nullopt),
        arena(threads) {}
  template <typename F>
  void execute(F&& f) {
    arena.execute(std::forward<F>(f));
  }
};
#endif

Renderer::Renderer(RendererOptions options) : options_(options) {
  if (options_.threads <= 0) options_.threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const int ts = options_.tileSize;
  if (ts != 0 && (ts < 8 || ts > 256 || (ts & (ts - 1)) != 0))
    throw std::invalid_argument("tile size must be 0 (automatic) or a power of two from 8 to 256, got " + std::to_string(ts));
  arena_ = std::make_unique<Arena>(options_.threads);
}

Renderer::~Renderer() = default;

int Renderer::threads() const { return options_.threads; }

// Tiles are the unit of parallel work, and a frame's fragments crowd into a few of them: on a
// small viewport the densest tile ran alone at the end (256×192 has 12 tiles of 64; dual peeling
// of dense.json took 1276 ms a frame with them and 932 ms with 48 tiles of 32, two threads).
// Tiles four times as wide as tall: a span within a tile is one batch of up to
// FragmentBatch::kCapacity (128) pixels, and each batch costs a fixed part on top of its
// fragments (dense's WBOIT accumulation, one thread: with tiles of 32, 1.75 times as many
// batches as with 64, 77 ms or 31 % longer, about 60 ns a batch more). 128×32 has the area of
// llvmpipe's 64×64, so as many tiles share out the work. Dense at 1080p, two threads, against
// 64×64 with batches of 64: WBOIT's accumulation 134 → 110–115 ms, opaque 35 → 30, peeling
// 1424–1611 → 1251–1284. On small viewports 64×16 (the area of 32×32): dense at 256×192, dual
// peeling 786–953 → 742–744 ms, WBOIT 9.7 → 8.0.
TileShape Renderer::tileShapeFor(int width, int height) const {
  if (options_.tileSize != 0) return {options_.tileSize, options_.tileSize};
  auto tiles = [&](TileShape s) {
    return int64_t((width + s.width - 1) / s.width) * int64_t((height + s.height - 1) / s.height);
  };
  const TileShape wide{128, 32};
  return tiles(wide) < 8 * int64_t(options_.threads) ? TileShape{64, 16} : wide;
}

void Renderer::parallelFor(size_t n, const std::function<void(size_t)>& body) {
  arena_->execute([&] { oitref::workerParallelFor(n, body); });
}

DrawStats Renderer::draw(Framebuffer& fb, const PipelineState& state, const Geometry& geometry,
                         const FragmentProgram& program) {
  return drawSequence(fb, state, {DrawCall{&geometry, program, 0}});
}

DrawStats Renderer::drawSequence(Framebuffer& fb, const PipelineState& state, const std::vector<DrawCall>& draws,
                                 const TileBands& bands) {
  fb.validate();
  for (const DrawCall& d : draws) d.geometry->validate();
  const detail::SetupContext context = makeContext(fb, state);
  const TileShape tiles = tileShapeFor(context.vw, context.vh);
  const detail::TileGrid grid(tiles.width, tiles.height, context.vx, context.vy, context.vw, context.vh);
  // The clears go tile by tile where the tiles cover the framebuffer; a smaller viewport's draw
  // clears everything first.
  const PendingClears clears = takeClears(fb, state.profile);
  const bool clearTiles = clears.any() && context.vx == 0 && context.vy == 0 && context.vw == fb.width() && context.vh == fb.height();
  if (clears.any() && !clearTiles) clears.applyEverywhere(fb);
  DrawStats stats;
  auto t0 = std::chrono::steady_clock::now();
  std::vector<detail::BinnedTriangles>& bins = arena_->bins;
  if (bins.size() < draws.size()) bins.resize(draws.size());
  std::vector<const Geometry*> geometries;
  for (const DrawCall& d : draws) geometries.push_back(d.geometry);
  arena_->execute([&] {
    detail::setupAndBin(geometries, context, grid, bins.data(), [](size_t n, auto&& body) { workerParallelFor(n, body); });
  });
  for (size_t d = 0; d < draws.size(); ++d) {
    stats.trianglesSubmitted += draws[d].geometry->triangleCount();
    stats.trianglesRasterized += bins[d].counters.rasterized;
    stats.trianglesNonFinite += bins[d].counters.nonFinite;
  }
  stats.setupMs = msSince(t0);
  double clipError = 0.0;
  for (size_t d = 0; d < draws.size(); ++d) clipError = std::max(clipError, bins[d].counters.clipErrorPixels);
  if (clipError > 1.0 / double(int64_t(1) << context.raster.subpixelBits)) {
    char text[64];
    std::snprintf(text, sizeof text, "%.3g", clipError);
    throw RasterPrecisionError(std::string("the rasterizer cannot place the clipped triangles of this frame within a sub-pixel "
                                           "step: their clip coordinates lie so far beyond the guard band that rounding may "
                                           "move a clipped vertex by up to ") + text +
                               " pixels (a camera zoomed to a tiny fov_y, or geometry that far off its axis); refused rather "
                               "than drawn from rounding errors");
  }

  t0 = std::chrono::steady_clock::now();
  std::vector<detail::FragmentCounters> perTile(size_t(grid.count()));
  if (bands.rows < 0) throw std::invalid_argument("TileBands::rows must not be negative");
  arena_->execute([&] {
    workerParallelFor(size_t(grid.count()), [&](size_t tile) {
      const detail::PixelRect rect = grid.tileRect(int(tile));
      if (clearTiles) clears.apply(fb, rect);
      std::optional<detail::FragmentStage> stage;  // made for the tile's first draw, kept for the rest
      const int rows = bands.rows > 0 ? bands.rows : rect.y1 - rect.y0;
      uint32_t triangles = 0;  // binned to the tile by all draws
      for (size_t d = 0; d < draws.size(); ++d) triangles += bins[d].tileStart[tile + 1] - bins[d].tileStart[tile];
      for (int y0 = rect.y0; y0 < rect.y1; y0 += rows) {
        const detail::PixelRect band{rect.x0, y0, rect.x1, std::min(rect.y1, y0 + rows)};
        bool begun = false;
        for (size_t d = 0; d < draws.size(); ++d) {
          const detail::BinnedTriangles& b = bins[d];
          if (b.tileStart[tile] == b.tileStart[tile + 1]) continue;
          if (!stage) stage.emplace(fb, state, draws[d].program, draws[d].geometry, viewportRect(context), draws[d].drawId);
          else stage->beginDraw(draws[d].program, draws[d].geometry, draws[d].drawId);
          if (!begun) {
            stage->beginTile(band);
            if (bands.begin) bands.begin({band.x0, band.y0, band.x1, band.y1}, triangles);
            begun = true;
          }
          detail::rasterizeTile(b, int(tile), band, context.raster.subpixelBits, options_.perFragment, *stage);
        }
        if (!begun) break;  // the tile has no triangle
        if (bands.end) bands.end({band.x0, band.y0, band.x1, band.y1});
      }
      if (stage) perTile[tile] = stage->counters();
    });
  });
  for (const auto& c : perTile) addCounters(stats, c);
  stats.rasterMs = msSince(t0);
  return stats;
}

DrawStats Renderer::drawFullscreen(Framebuffer& fb, const PipelineState& state, const FragmentProgram& program) {
  fb.validate();
  const detail::SetupContext context = makeContext(fb, state);
  takeClears(fb, state.profile).applyEverywhere(fb);
  // Every pixel is one fragment that sees only its own pixel, so the order is free: bands of
  // whole rows, which read and write the attachments as sequential streams the hardware
  // prefetches (a tile's rows lie a page apart).
  constexpr int kBandRows = 4;
  const detail::PixelRect viewport = viewportRect(context);
  const int bands = (context.vh + kBandRows - 1) / kBandRows;
  DrawStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<detail::FragmentCounters> perBand(static_cast<size_t>(bands));
  arena_->execute([&] {
    workerParallelFor(size_t(bands), [&](size_t band) {
      detail::FragmentStage stage(fb, state, program, nullptr, viewport);
      const int y0 = context.vy + int(band) * kBandRows, y1 = std::min(y0 + kBandRows, context.vy + context.vh);
      for (int y = y0; y < y1; ++y) {
        if (options_.perFragment)
          for (int x = viewport.x0; x < viewport.x1; ++x) stage.fullscreenPixel(x, y);
        else
          stage.fullscreenSpan(y, viewport.x0, viewport.x1);
      }
      perBand[band] = stage.counters();
    });
  });
  for (const auto& c : perBand) addCounters(stats, c);
  stats.rasterMs = msSince(t0);
  return stats;
}

}  // namespace oitref
