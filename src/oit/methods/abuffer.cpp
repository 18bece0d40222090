// The exact per-pixel sorted A-buffer: every transparent fragment that passes the opaque depth
// test is stored per pixel — window depth, view depth, straight RGBA in fp32, object and
// primitive id — then sorted front to back by view depth (window depth, then submission order,
// break ties: the sort is stable over fragments stored in submission order), and composited back
// to front with OVER, C = c·α + C·(1 − α), in fp32 or (precision=double) in double.
//
// The storing pass draws each tile in bands of rows (renderer.h's TileBands), as a tiling GPU
// keeps a tile's storage on chip: a band's lists are laid out when it begins, filled by the
// fragment shader, and sorted, composited and stored into the presented images by the same
// worker when it ends, while they are in its cache (abuffer_band.h). Each band's pixels belong to
// one worker, so the per-pixel writes are race-free and in submission order. A band's lists are
// laid out one of two ways (option `store`):
//   bounded — each list at a fixed stride of the triangles that can reach the band (no pixel
//     holds more fragments than triangles reach it), with no counting pass; `auto` takes it where
//     the scene's transparent triangles are few enough that a band's store stays small;
//   counted — as a GPU A-buffer with a prefix sum would: a counting pass first (stopped, as soon
//     as the fragments cannot fit, with an error naming the deepest pixel, never an out-of-memory
//     kill), and each band's lists one after another. Always where the whole frame's lists are
//     kept for the result (lists=keep): each band's rows are copied there.
// Either way the same fragments are stored in the same order and resolved by the same code.
#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "methods/abuffer_band.h"
#include "methods/fragment_bound.h"
#include "methods/method_common.h"
#include "methods/methods.h"
#include "util/huge_pages.h"

namespace oitref::methods {
namespace {

using StoredFragment = TransparentFragment;

// Thrown by a pass's shader, or a band's end, to end the pass early (caught in render()).
struct TooManyFragments {};

// A number per rendered frame, so that a worker's pending count never carries into another frame.
uint64_t nextFrameId() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

// Rows a band: a band of a 128-pixel-wide tile holds 512 lists (0.9 MB at dense's 71 layers).
// Dense at 1080p, two threads, store+resolve: 2 rows 223–242 ms, 4 rows 217–239, 8 rows 223–265,
// 32 (whole tiles) 398; each band walks its tile's triangles again.
constexpr int kBandRows = 4;
// The most transparent triangles for bounded bands: a band of up to 256×4 pixels (the widest
// tiles) then stores at most 1024 × 1026 fragments, 32 MiB, a worker.
constexpr uint64_t kBoundedTriangles = 1024;

uint64_t transparentTriangles(const SceneGeometry& geometry) {
  uint64_t n = 0;
  for (const ScenePart& part : geometry.parts) n += part.transparent ? part.triangleCount() : 0;
  return n;
}

class Abuffer final : public Method {
 public:
  explicit Abuffer(const MethodOptions& o)
      : useDouble_(o.is("precision", "double")), keepLists_(o.is("lists", "keep")),
        maxFragments_(uint64_t(o.number("max_fragments"))), store_(o.choice<Store>("store")) {
    if (keepLists_ && store_ == Store::Bounded)
      throw std::invalid_argument("option 'lists': lists=keep needs store=counted or store=auto (the kept lists lie one after "
                                  "another, from the counting pass)");
  }
  const MethodInfo& info() const override { return abufferInfo(); }
  std::vector<AttachmentDecl> attachments() const override { return AttachmentList().declared(); }
  // The frame's own buffers, and, where the lists are kept, the fragments that the geometry alone
  // shows it must store (fragment_bound.h): a frame that cannot fit is refused before anything is
  // allocated. The fragments themselves are counted, and checked again, by the counting pass;
  // the bands' stores are checked before the storing pass.
  std::vector<MemoryItem> memoryNeed(int width, int height, const SceneGeometry& geometry) const override {
    std::vector<MemoryItem> items = frameBuffers(width, height, geometry, !bounded(geometry));
    if (!keepLists_) return items;
    const uint64_t fragments = transparentFragmentsAtLeast(geometry, width, height);
    items.push_back({"transparent fragments, at least " + std::to_string(fragments) + " (" +
                         std::to_string(sizeof(StoredFragment)) + " B each; those of the triangles in front of every opaque one)",
                     fragments * sizeof(StoredFragment)});
    return items;
  }

  FrameResult render(const FrameContext& context) override {
    if (const uint64_t least = transparentFragmentsAtLeast(context.geometry, context.width, context.height); least > maxFragments_)
      throw std::runtime_error("A-buffer: at least " + std::to_string(least) +
                               " fragments (those of the triangles in front of every opaque one) exceed max_fragments=" +
                               std::to_string(maxFragments_) + ". Raise it with --set max_fragments=N or render smaller.");
    FrameResult result;
    FrameTargets t(attachments(), context);
    PassRunner run(context, result);
    run.opaquePass(t);
    const int w = context.width, h = context.height;
    Framebuffer depthOnly;
    depthOnly.depth = &t.depth();
    const PipelineState st = transparentState(context.profile, BlendState{});
    const TileShape tile = context.renderer.tileShapeFor(w, h);
    const uint64_t threads = uint64_t(context.renderer.threads()), bandPixels = uint64_t(tile.width) * kBandRows;
    spareBands_.clear();  // every band's store is free between frames (a failed frame may not have given one back)
    for (std::unique_ptr<AbufferBand>& b : bands_) spareBands_.push_back(b.get());

    // Bounded bands where the scene allows them and their stores fit.
    const uint64_t triangles = transparentTriangles(context.geometry);
    uint64_t known = 0;
    for (const MemoryItem& i : frameBuffers(w, h, context.geometry, false)) known += i.bytes;
    const uint64_t bandRecords = bandPixels * AbufferBand::boundedStride(triangles);  // a bounded band's store at most
    const uint64_t boundedBytes = threads * bandRecords * AbufferBand::kRecordBytes;
    const bool useBounds = bounded(context.geometry) && known + boundedBytes <= context.memoryLimit;
    if (store_ == Store::Bounded && !useBounds)
      throw std::runtime_error("A-buffer: store=bounded needs " + formatBytes(boundedBytes) + " for the bands' stores (" +
                               std::to_string(bandPixels) + " lists of up to " + std::to_string(triangles) +
                               " fragments, the transparent triangles, for each of " + std::to_string(threads) +
                               " threads), beside the frame's own " + formatBytes(known) + ", above the memory limit of " +
                               formatBytes(context.memoryLimit) + ". Use store=counted or raise --memory-limit.");
    if (useBounds) {  // what an earlier frame kept beyond this one's need goes
      std::vector<uint32_t>().swap(count_);
      for (std::unique_ptr<AbufferBand>& b : bands_) b->shrinkTo(bandRecords);
    }
    const FrameTally tally = useBounds ? storeBounded(context, t, run, depthOnly, st, triangles)
                                       : storeCounted(context, t, run, depthOnly, st, tile);

    result.stats.fragments = tally.fragments;
    result.stats.depthComplexityMax = tally.deepest;
    result.stats.depthComplexityMean = double(tally.fragments) / (double(w) * double(h));
    result.stats.pixelsWithTransparency = tally.covered;
    uint64_t bandStore = 0;
    for (const std::unique_ptr<AbufferBand>& b : bands_) bandStore += b->storeBytes();
    result.stats.fragmentStorageBytes = bandStore + tally.listBytes;
    t.finish(result, AttachmentList::kOpaque);
    if (keepLists_) result.fragmentLists = std::move(kept_);
    kept_ = {};
    return result;
  }

 private:
  struct FrameTally : AbufferBand::Tally {
    uint64_t listBytes = 0;  // the kept lists and their offsets
  };

  enum class Store { Auto, Counted, Bounded };  // in the order of the option's choices
  bool bounded(const SceneGeometry& geometry) const {
    return store_ == Store::Bounded || (store_ == Store::Auto && !keepLists_ && transparentTriangles(geometry) <= kBoundedTriangles);
  }

  // The attachments and copies of every method and, with a counting pass, the counts and (with
  // kept lists) their offsets.
  std::vector<MemoryItem> frameBuffers(int width, int height, const SceneGeometry& geometry, bool counted) const {
    std::vector<MemoryItem> items = Method::memoryNeed(width, height, geometry);
    if (counted)
      items.push_back({keepLists_ ? "fragment counts and list offsets (12 B/pixel)" : "fragment counts (4 B/pixel)",
                       uint64_t(width) * uint64_t(height) * (keepLists_ ? 12 : 4)});
    return items;
  }

  // The storing pass, which resolves each band as it ends. `layOut` lays out the band's lists;
  // `ended(band)` runs after its resolve, before its store is given back.
  template <typename LayOut, typename Ended>
  void storeAndResolve(const FrameContext& context, FrameTargets& t, PassRunner& run, Framebuffer& depthOnly,
                       const PipelineState& st, const LayOut& layOut, const Ended& ended) {
    Image &opaque = t.opaque(), &analysis = t.analysis();
    TileBands bands;
    bands.rows = kBandRows;
    bands.begin = [&](const TileRect& r, uint32_t reaching) { layOut(*(currentBand = takeBand()), r, reaching); };
    bands.end = [&](const TileRect& r) {
      AbufferBand& b = *std::exchange(currentBand, nullptr);
      for (int y = r.y0; y < r.y1; ++y) b.resolveRow(y, opaque, analysis, context.profile, useDouble_);
      ended(b);
      giveBand(&b);
    };
    run.transparentBatchPass("store+resolve", depthOnly, st, [](const FragmentBatch& in, const glm::vec4* c, FragmentBatchOutput&) {
      currentBand->store(in, c);
    }, false, false, {}, true, true, bands);
  }

  // Bounded bands: each list at a stride of the triangles that reach the band, no more than the
  // scene's transparent triangles. The budget is checked as the bands end.
  FrameTally storeBounded(const FrameContext& context, FrameTargets& t, PassRunner& run, Framebuffer& depthOnly,
                          const PipelineState& st, uint64_t triangles) {
    FrameTally frame;
    std::mutex tallyMutex;
    try {
      storeAndResolve(context, t, run, depthOnly, st,
                      [triangles](AbufferBand& b, const TileRect& r, uint32_t reaching) {
                        b.layOutBounded(r, std::min<uint64_t>(reaching, triangles));
                      },
                      [&](const AbufferBand& b) {
                        const AbufferBand::Tally band = b.tally();
                        if (band.deepest > b.start[1] - b.start[0])  // the renderer's bound broken: lists overran
                          throw std::logic_error("A-buffer: a pixel got more fragments than triangles reach its band");
                        const std::lock_guard<std::mutex> lock(tallyMutex);
                        frame.add(band);
                        if (frame.fragments > maxFragments_) throw TooManyFragments{};
                      });
    } catch (const TooManyFragments&) {
      throw std::runtime_error("A-buffer: more than max_fragments=" + std::to_string(maxFragments_) +
                               " fragments (the storing pass stopped there). Raise it with --set max_fragments=N or render smaller.");
    }
    return frame;
  }

  // Counted bands: a counting pass, the checks against the budget and the memory limit, and each
  // band's lists one after another (with lists=keep, copied into the frame's lists).
  FrameTally storeCounted(const FrameContext& context, FrameTargets& t, PassRunner& run, Framebuffer& depthOnly,
                          const PipelineState& st, TileShape tile) {
    const int w = context.width, h = context.height;
    const size_t pixels = size_t(w) * size_t(h);
    // The fragments that fit beside the frame's own buffers and under max_fragments. The counting
    // pass stops as soon as it has counted more (a 16384² frame of `dense` counted for five
    // minutes before its total was refused): each worker adds its count to the shared total every
    // few thousand fragments, so what has been added never exceeds the true count, and a frame
    // that fits is never stopped. Without kept lists the frame stores one band a worker at a
    // time, checked once the count is known.
    uint64_t known = 0;
    for (const MemoryItem& i : frameBuffers(w, h, context.geometry, true)) known += i.bytes;
    const uint64_t spare = context.memoryLimit > known ? context.memoryLimit - known : 0;
    const uint64_t fitting = keepLists_ ? std::min(maxFragments_, spare / sizeof(StoredFragment)) : maxFragments_;
    count_.assign(pixels, 0);  // kept between frames: no pages to fault in and zero
    uint32_t* const count = count_.data();
    std::atomic<uint64_t> counted{0};
    const uint64_t frameId = nextFrameId();
    bool stopped = false;
    try {
      run.transparentPositionPass("count", depthOnly, st, [&](const FragmentBatch& in, FragmentBatchOutput&) {
        uint32_t* row = count + size_t(in.y) * w;
        if (in.x[in.count - 1] - in.x[0] == in.count - 1) {  // a run of pixels (x ascending): in lanes
          uint32_t* run = row + in.x[0];
          for (int i = 0; i < in.count; ++i) ++run[i];
        } else {
          for (int i = 0; i < in.count; ++i) ++row[in.x[i]];
        }
        thread_local struct { uint64_t frame = 0, pending = 0; } local;
        if (local.frame != frameId) local = {frameId, 0};
        if ((local.pending += uint64_t(in.count)) < 4096) return;
        const uint64_t total = counted.fetch_add(local.pending, std::memory_order_relaxed) + local.pending;
        local.pending = 0;
        if (total > fitting) throw TooManyFragments{};
      }, false);  // reads only the columns: runs that surely pass the depth test are not interpolated
    } catch (const TooManyFragments&) {
      stopped = true;
    }
    if (stopped) {  // what is known then: the frame needs more than `fitting` fragments
      if (fitting == maxFragments_)
        throw std::runtime_error("A-buffer: more than max_fragments=" + std::to_string(maxFragments_) +
                                 " fragments (the count stopped there). Raise it with --set max_fragments=N or render smaller.");
      throw std::runtime_error("A-buffer: more than " + std::to_string(fitting) + " fragments (" +
                               formatBytes(fitting * sizeof(StoredFragment)) + "), which is what fits beside the frame's own " +
                               formatBytes(known) + " under the memory limit of " + formatBytes(context.memoryLimit) +
                               " (the count stopped there). Render smaller or raise --memory-limit.");
    }
    const uint64_t total = std::accumulate(count, count + pixels, uint64_t(0));
    const size_t deepest = size_t(std::max_element(count, count + pixels) - count);
    const std::string deepestText = "; the deepest pixel (" + std::to_string(deepest % w) + "," + std::to_string(deepest / w) +
                                    ") has " + std::to_string(count[deepest]) + " layers.";
    // What the frame stores: each band's lists while it is drawn (at most one band a worker), and
    // with lists=keep every list besides.
    const uint64_t threads = uint64_t(context.renderer.threads());
    const uint64_t largestBand = largestBandFragments(w, h, tile);
    const uint64_t bandBytes = threads * largestBand * (AbufferBand::kRecordBytes + (keepLists_ ? AbufferBand::kIdBytes : 0));
    const uint64_t fragmentBytes = (keepLists_ ? total * sizeof(StoredFragment) : 0) + bandBytes;
    if (known + fragmentBytes > context.memoryLimit)
      throw std::runtime_error("A-buffer: " + std::to_string(total) + " fragments need " +
                               (keepLists_ ? formatBytes(total * sizeof(StoredFragment)) + " for their lists and " : "") +
                               formatBytes(bandBytes) + " for the bands resolved at once (up to " + std::to_string(largestBand) +
                               " fragments in a band of " + std::to_string(tile.width) + "x" + std::to_string(kBandRows) +
                               " pixels, one band for each of " + std::to_string(threads) + " threads), beside the frame's own " +
                               formatBytes(known) + ", above the memory limit of " + formatBytes(context.memoryLimit) +
                               deepestText + " Render smaller or raise --memory-limit.");
    if (total > maxFragments_)
      throw std::runtime_error("A-buffer: " + std::to_string(total) + " fragments exceed max_fragments=" +
                               std::to_string(maxFragments_) + " (" + std::to_string(total * sizeof(StoredFragment) >> 20) +
                               " MiB)" + deepestText + " Raise it with --set max_fragments=N or render smaller.");
    for (std::unique_ptr<AbufferBand>& b : bands_) b->shrinkTo(largestBand);  // a larger store from an earlier frame goes

    // The whole frame's lists, for FrameResult::fragmentLists, only where they are asked for: each
    // band's rows are copied there, one run of lists a row.
    FragmentLists& lists = kept_;
    if (keepLists_) {
      lists.width = w, lists.height = h;
      lists.start.assign(pixels + 1, 0);
      for (size_t p = 0; p < pixels; ++p) lists.start[p + 1] = lists.start[p] + count[p];
      if (context.pool) {
        lists.fragments = context.pool->takeFragments(total);
      } else {
        util::reserveOnHugePages(lists.fragments, total);
        lists.fragments.resize(total);
      }
    }
    storeAndResolve(context, t, run, depthOnly, st,
                    [this, count, w](AbufferBand& b, const TileRect& r, uint32_t) { b.layOutCounted(r, count, w, keepLists_); },
                    [&](const AbufferBand& b) {
                      if (!keepLists_) return;
                      const TileRect& r = b.rect;
                      for (int y = r.y0, i = 0; y < r.y1; ++y)
                        for (int x = r.x0; x < r.x1; ++x, ++i)
                          b.copyList(size_t(i), lists.fragments.data() + lists.start[size_t(y) * w + size_t(x)]);
                    });
    FrameTally frame;
    frame.fragments = total;
    frame.deepest = count[deepest];
    for (size_t p = 0; p < pixels; ++p) frame.covered += count[p] > 0;
    frame.listBytes = keepLists_ ? total * sizeof(StoredFragment) + (pixels + 1) * sizeof(uint64_t) : 0;
    return frame;
  }

  // The most fragments of one band of the renderer's tiles (bands start every kBandRows rows of
  // a tile, and tiles every tile.height rows from row 0, a multiple of kBandRows).
  uint64_t largestBandFragments(int w, int h, TileShape tile) const {
    const int across = (w + tile.width - 1) / tile.width;
    std::vector<uint64_t> band(static_cast<size_t>(across));
    uint64_t largest = 0;
    for (int y = 0; y < h; ++y) {
      const uint32_t* row = count_.data() + size_t(y) * size_t(w);
      for (int x = 0; x < w; ++x) band[size_t(x / tile.width)] += row[x];
      if ((y + 1) % kBandRows != 0 && y + 1 != h && (y + 1) % tile.height != 0) continue;
      for (uint64_t& b : band) largest = std::max(largest, std::exchange(b, 0));
    }
    return largest;
  }

  // A band's store, kept between bands and frames: as many as bands drawn at once (one a worker).
  AbufferBand* takeBand() {
    const std::lock_guard<std::mutex> lock(bandsMutex_);
    if (spareBands_.empty()) return bands_.emplace_back(std::make_unique<AbufferBand>()).get();
    AbufferBand* b = spareBands_.back();
    spareBands_.pop_back();
    return b;
  }
  void giveBand(AbufferBand* b) {
    const std::lock_guard<std::mutex> lock(bandsMutex_);
    spareBands_.push_back(b);
  }

  static thread_local AbufferBand* currentBand;  // the band this worker is drawing
  bool useDouble_;
  bool keepLists_;
  uint64_t maxFragments_;
  Store store_;
  std::vector<uint32_t> count_;  // each pixel's fragments, from the counting pass
  FragmentLists kept_;           // the frame's lists while it is drawn (lists=keep)
  std::mutex bandsMutex_;
  std::vector<std::unique_ptr<AbufferBand>> bands_;
  std::vector<AbufferBand*> spareBands_;
};

thread_local AbufferBand* Abuffer::currentBand = nullptr;

}  // namespace

const MethodInfo& abufferInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "abuffer",
      "exact per-pixel sorted A-buffer (ground truth), OVER back to front",
      {{"precision", "float", "arithmetic of the OVER composite", {"float", "double"}},
       {"max_fragments", "50000000", "fragment budget (32 bytes each where the lists are kept); exceeding it is an error", {},
        OptionNumber::integer(1, 0x1p40)},
       {"lists", "none", "whether the frame's result keeps every pixel's fragments (FrameResult::fragmentLists)",
        {"none", "keep"}},
       {"store", "auto", "how a band's lists are laid out: counted (a counting pass first) or bounded (no counting pass, "
        "each list as long as the triangles that reach the band); auto: bounded for at most 1024 transparent triangles",
        {"auto", "counted", "bounded"}}}};
    i.studyVariants = {{{"precision", "double"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> abufferFactory(const MethodOptions& o) {
  return std::make_unique<Abuffer>(o);
}

}  // namespace oitref::methods
