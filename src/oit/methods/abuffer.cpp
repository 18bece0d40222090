// The exact per-pixel sorted A-buffer: every transparent fragment that passes the opaque depth
// test is stored per pixel — window depth, view depth, straight RGBA in fp32, object and
// primitive id — then sorted front to back by view depth (window depth, then submission order,
// break ties: the sort is stable over fragments stored in submission order), and composited back
// to front with OVER, C = c·α + C·(1 − α), in fp32 or (precision=double) in double.
//
// Storage is built as a GPU A-buffer with a prefix sum would: a counting pass, a check against
// the `max_fragments` budget (an error naming the deepest pixel, never an out-of-memory kill),
// then a storing pass. The storing pass draws each tile in bands of rows (renderer.h's
// TileBands), as a tiling GPU keeps a tile's storage on chip: a band's lists are laid out from
// the counts when it begins, filled by the fragment shader, and sorted, composited and stored
// into the presented images by the same worker when it ends, while they are in its cache. Each
// band's pixels belong to one worker, so the per-pixel writes are race-free and in submission
// order. The whole frame's lists are kept for the result only on request (lists=keep).
#include <algorithm>
#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <utility>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "methods/depth_order.h"
#include "methods/fragment_bound.h"
#include "methods/method_common.h"
#include "methods/methods.h"
#include "util/huge_pages.h"

namespace oitref::methods {
namespace {

using StoredFragment = TransparentFragment;

// Thrown by the counting pass's shader to end the pass early (caught in render()).
struct TooManyFragments {};

// A number per rendered frame, so that a worker's pending count never carries into another frame.
uint64_t nextFrameId() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

// OVER of one layer onto what lies behind it: c·α + C·(1 − α), each operation rounded in V — per
// channel (V = S = float or double) or per lane of a vector of floats (S = float).
template <typename V, typename S>
V over(V color, V alpha, V behind) {
  const V front = color * alpha, under = behind * (S(1) - alpha);
  return front + under;
}

// OVER back to front of the list's fragments in `order` (front to back), onto both backgrounds.
template <typename Real>
void compositeBackToFront(const StoredFragment* list, const uint32_t* order, size_t n, const glm::vec3 background[2],
                          glm::vec3 result[2]) {
  Real c[2][3];
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) c[t][k] = Real(background[t][k]);
  for (size_t i = n; i-- > 0;) {
    const glm::vec4& color = list[order[i]].color;
    const Real a = Real(color.a);
    for (int t = 0; t < 2; ++t)
      for (int k = 0; k < 3; ++k) c[t][k] = over<Real, Real>(Real(color[k]), a, c[t][k]);
  }
  for (int t = 0; t < 2; ++t) result[t] = {float(c[t][0]), float(c[t][1]), float(c[t][2])};
}

// compositeBackToFront<float> with both backgrounds' channels in the lanes of one vector (r, g, b
// of target 0 in lanes 0–2, of target 1 in lanes 4–6; lanes 3 and 7 compute α·α and are never
// read): the same operations per channel, one vector operation for all six.
class FloatLanesOver {
 public:
  explicit FloatLanesOver(const glm::vec3 background[2])
      : c_{background[0].x, background[0].y, background[0].z, 0.0f, background[1].x, background[1].y, background[1].z, 0.0f} {}
  void layer(const glm::vec4& color) {
#if defined(__AVX__)
    // Loads that broadcast: no shuffle (the pair's layers were bound by the shuffle units).
    const v8 both = v8(_mm256_broadcast_ps(reinterpret_cast<const __m128*>(&color))), alpha = v8(_mm256_broadcast_ss(&color.a));
#else
    v4 c;
    std::memcpy(&c, &color, sizeof c);
    const float a = color.a;
    const v8 both = __builtin_shufflevector(c, c, 0, 1, 2, 3, 0, 1, 2, 3), alpha = {a, a, a, a, a, a, a, a};
#endif
    c_ = over<v8, float>(both, alpha, c_);
  }
  void finish(glm::vec3 result[2]) const {
    result[0] = {c_[0], c_[1], c_[2]};
    result[1] = {c_[4], c_[5], c_[6]};
  }

 private:
  typedef float v4 __attribute__((vector_size(16)));
  typedef float v8 __attribute__((vector_size(32)));
  v8 c_;
};

// compositeBackToFront<float> of two lists, their layers side by side (each layer waits for the
// one behind it; the other list's layers fill that wait): the back layers of the longer list that
// the other has no partner for first, then both together.
void compositePairBackToFront(const StoredFragment* listA, const uint32_t* orderA, size_t na, const glm::vec3 backgroundA[2],
                              glm::vec3 resultA[2], const StoredFragment* listB, const uint32_t* orderB, size_t nb,
                              const glm::vec3 backgroundB[2], glm::vec3 resultB[2]) {
  FloatLanesOver a(backgroundA), b(backgroundB);
  size_t i = na, j = nb;
  for (; i > j; --i) a.layer(listA[orderA[i - 1]].color);
  for (; j > i; --j) b.layer(listB[orderB[j - 1]].color);
  for (; i > 0; --i, --j) a.layer(listA[orderA[i - 1]].color), b.layer(listB[orderB[j - 1]].color);
  a.finish(resultA);
  b.finish(resultB);
}

// The lists of one band of a tile (renderer.h's TileBands), stored by the worker that draws it and
// resolved by it as soon as the band's last fragment is in: the band's lists stay in that
// worker's cache (a band of 128×8 pixels with dense's 71 layers holds 2.3 MB), where a frame's
// lists in memory would take every record's line from memory and back (1.7 GB at 1080p).
struct BandLists {
  TileRect rect;
  int width = 0;
  std::vector<uint64_t> start;   // band pixel i = (y − y0)·width + (x − x0) owns [start[i], start[i + 1])
  std::vector<uint32_t> filled;  // how many of each pixel's fragments are stored
  std::vector<StoredFragment> fragments;
  std::vector<glm::vec4> texels[2];    // a row's backgrounds in both presented images
  std::vector<glm::vec4> resolved[2];  // the colours of its pixels with fragments, in order
  std::vector<int> columns;            // and their columns
  std::vector<uint32_t> orders[2];
  DepthOrder depthOrder;
};

class Abuffer final : public Method {
 public:
  explicit Abuffer(const MethodOptions& o)
      : useDouble_(o.is("precision", "double")), keepLists_(o.is("lists", "keep")),
        maxFragments_(uint64_t(o.number("max_fragments"))) {}
  const MethodInfo& info() const override { return abufferInfo(); }
  std::vector<AttachmentDecl> attachments() const override { return AttachmentList().declared(); }
  // The frame's own buffers, and, where the lists are kept, the fragments that the geometry alone
  // shows it must store (fragment_bound.h): a frame that cannot fit is refused before anything is
  // allocated. The fragments themselves are counted, and checked again, by the counting pass.
  std::vector<MemoryItem> memoryNeed(int width, int height, const SceneGeometry& geometry) const override {
    std::vector<MemoryItem> items = frameBuffers(width, height, geometry);
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
    const size_t pixels = size_t(w) * size_t(h);
    Framebuffer depthOnly;
    depthOnly.depth = &t.depth();
    const PipelineState st = transparentState(context.profile, BlendState{});

    // The fragments that fit beside the frame's own buffers and under max_fragments. The counting
    // pass stops as soon as it has counted more (a 16384² frame of `dense` counted for five
    // minutes before its total was refused): each worker adds its count to the shared total every
    // few thousand fragments, so what has been added never exceeds the true count, and a frame
    // that fits is never stopped. Without kept lists the frame stores one band a worker at a time,
    // checked once the count is known.
    uint64_t known = 0;
    for (const MemoryItem& i : frameBuffers(w, h, context.geometry)) known += i.bytes;
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
    const TileShape tile = context.renderer.tileShapeFor(w, h);
    const uint64_t largestBand = largestBandFragments(w, h, tile);
    const uint64_t bandBytes = uint64_t(context.renderer.threads()) * largestBand * sizeof(StoredFragment);
    const uint64_t fragmentBytes = (keepLists_ ? total * sizeof(StoredFragment) : 0) + bandBytes;
    if (known + fragmentBytes > context.memoryLimit)
      throw std::runtime_error("A-buffer: " + std::to_string(total) + " fragments need " +
                               (keepLists_ ? formatBytes(total * sizeof(StoredFragment)) + " for their lists and " : "") +
                               formatBytes(bandBytes) + " for the bands resolved at once (up to " + std::to_string(largestBand) +
                               " fragments in a band of " + std::to_string(tile.width) + "x" + std::to_string(kBandRows) +
                               " pixels, one band for each of " + std::to_string(context.renderer.threads()) +
                               " threads), beside the frame's own " + formatBytes(known) + ", above the memory limit of " +
                               formatBytes(context.memoryLimit) + deepestText + " Render smaller or raise --memory-limit.");
    if (total > maxFragments_)
      throw std::runtime_error("A-buffer: " + std::to_string(total) + " fragments exceed max_fragments=" +
                               std::to_string(maxFragments_) + " (" + std::to_string(total * sizeof(StoredFragment) >> 20) +
                               " MiB)" + deepestText + " Raise it with --set max_fragments=N or render smaller.");
    for (std::unique_ptr<BandLists>& b : bands_)  // a larger store kept from an earlier frame goes
      if (b->fragments.capacity() > largestBand) std::vector<StoredFragment>().swap(b->fragments);

    // The whole frame's lists, for FrameResult::fragmentLists, only where they are asked for: each
    // band's resolve copies its lists there, one run of fragments a row.
    std::vector<uint64_t> start;
    std::vector<StoredFragment> fragments;
    if (keepLists_) {
      start.assign(pixels + 1, 0);
      for (size_t p = 0; p < pixels; ++p) start[p + 1] = start[p] + count[p];
      if (context.pool) {
        fragments = context.pool->takeFragments(total);
      } else {
        util::reserveOnHugePages(fragments, total);
        fragments.resize(total);
      }
    }
    Image &opaque = t.opaque(), &analysis = t.analysis();
    TileBands bands;
    bands.rows = kBandRows;
    bands.begin = [&](const TileRect& r) { beginBand(r, count, w); };
    bands.end = [&](const TileRect& r) {
      BandLists& b = *std::exchange(currentBand, nullptr);
      for (int y = r.y0; y < r.y1; ++y) resolveRow(b, y, opaque, analysis, context.profile);
      if (keepLists_)
        for (int y = r.y0; y < r.y1; ++y) {
          const size_t i = size_t(y - r.y0) * size_t(b.width), p = size_t(y) * w + size_t(r.x0);
          std::copy(b.fragments.data() + b.start[i], b.fragments.data() + b.start[i + size_t(b.width)],
                    fragments.data() + start[p]);
        }
      giveBand(&b);
    };
    run.transparentBatchPass("store+resolve", depthOnly, st, [](const FragmentBatch& in, const glm::vec4* c, FragmentBatchOutput&) {
      BandLists& b = *currentBand;
      const size_t row = size_t(in.y - b.rect.y0) * size_t(b.width) - size_t(b.rect.x0);
      for (int i = 0; i < in.count; ++i) {
        const size_t p = row + size_t(in.x[i]);
        b.fragments[b.start[p] + b.filled[p]++] = {in.depth[i], in.viewDepth[i], c[i], in.drawId, in.primitiveId};
      }
    }, false, false, {}, true, true, bands);

    uint64_t covered = 0;
    for (size_t p = 0; p < pixels; ++p) covered += count[p] > 0;
    result.stats.fragments = total;
    result.stats.depthComplexityMax = count[deepest];
    result.stats.depthComplexityMean = double(total) / double(pixels);
    result.stats.pixelsWithTransparency = covered;
    uint64_t bandStore = 0;
    for (const std::unique_ptr<BandLists>& b : bands_) bandStore += b->fragments.capacity() * sizeof(StoredFragment);
    result.stats.fragmentStorageBytes = bandStore + (keepLists_ ? total * sizeof(StoredFragment) + (pixels + 1) * sizeof(uint64_t) : 0);
    t.finish(result, AttachmentList::kOpaque);
    if (keepLists_) result.fragmentLists = {context.width, context.height, std::move(start), std::move(fragments)};
    return result;
  }

 private:
  // Rows a band: a band of a 128-pixel-wide tile holds 512 lists (1.2 MB at dense's 71 layers).
  // Dense at 1080p, two threads, store+resolve: 2 rows 223–242 ms, 4 rows 217–239, 8 rows
  // 223–265, 32 (whole tiles) 398; each band costs a walk over its tile's triangles.
  static constexpr int kBandRows = 4;

  // The attachments and copies of every method, the counts and, with kept lists, their heads.
  std::vector<MemoryItem> frameBuffers(int width, int height, const SceneGeometry& geometry) const {
    std::vector<MemoryItem> items = Method::memoryNeed(width, height, geometry);
    items.push_back({keepLists_ ? "fragment counts and list offsets (12 B/pixel)" : "fragment counts (4 B/pixel)",
                     uint64_t(width) * uint64_t(height) * (keepLists_ ? 12 : 4)});
    return items;
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
  // A band's lists laid out from the counts: the worker's store for it until the band ends.
  void beginBand(const TileRect& r, const uint32_t* count, int w) {
    BandLists& b = *(currentBand = takeBand());
    b.rect = r;
    b.width = r.x1 - r.x0;
    const size_t n = size_t(b.width) * size_t(r.y1 - r.y0);
    b.start.resize(n + 1);
    b.filled.assign(n, 0);
    uint64_t at = 0;
    for (int y = r.y0, i = 0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x, ++i) b.start[size_t(i)] = at, at += count[size_t(y) * size_t(w) + size_t(x)];
    b.start[n] = at;
    if (b.fragments.size() < at) {  // exactly the band's fragments: the memory check counts no more
      b.fragments.clear();
      b.fragments.reserve(at);
      b.fragments.resize(at);
    }
  }
  // Row y of band b resolved into both presented images: each list sorted (the stored lists stay
  // in submission order; the resolve sorts positions) and composited onto the pixel's background,
  // then stored with α = 1 by the format's rule under the profile (Image::storeRow). Two pixels
  // at a time, side by side (DepthOrder::sortPair, compositePairBackToFront): each insertion and
  // each layer waits for the one before, and the other pixel's work fills that wait.
  void resolveRow(BandLists& b, int y, Image& opaque, Image& analysis, const Profile& profile) const {
    const size_t first = size_t(y - b.rect.y0) * size_t(b.width);
    const int n = b.width;
    if (b.start[first + size_t(n)] == b.start[first]) return;  // no fragments in this row of the band
    for (int t = 0; t < 2; ++t) {
      b.texels[t].resize(size_t(n));
      (t == 0 ? opaque : analysis).fetchRun(y, b.rect.x0, n, b.texels[t].data());
    }
    auto list = [&](int i) { return b.fragments.data() + b.start[first + size_t(i)]; };
    auto length = [&](int i) { return uint32_t(b.start[first + size_t(i) + 1] - b.start[first + size_t(i)]); };
    auto backgrounds = [&](int i, glm::vec3 out[2]) {
      out[0] = glm::vec3(b.texels[0][size_t(i)]), out[1] = glm::vec3(b.texels[1][size_t(i)]);
    };
    int resolved = 0;  // pixels resolved so far
    b.columns.resize(size_t(n)), b.resolved[0].resize(size_t(n)), b.resolved[1].resize(size_t(n));
    auto store = [&](int i, const glm::vec3 out[2]) {
      b.columns[size_t(resolved)] = b.rect.x0 + i;
      for (int t = 0; t < 2; ++t) b.resolved[t][size_t(resolved)] = glm::vec4(out[t], 1.0f);
      ++resolved;
    };
    const auto composite = useDouble_ ? compositeBackToFront<double> : compositeBackToFront<float>;
    std::vector<uint32_t>* orders = b.orders;
    int waiting = -1;  // a pixel whose list waits for a second one
    for (int i = 0; i < n; ++i) {
      if (length(i) == 0) continue;
      if (waiting < 0) {
        waiting = i;
        continue;
      }
      const int one = std::exchange(waiting, -1);
      orders[0].resize(length(one)), orders[1].resize(length(i));
      b.depthOrder.sortPair(list(one), length(one), orders[0].data(), list(i), length(i), orders[1].data());
      glm::vec3 under[2][2], out[2][2];
      backgrounds(one, under[0]), backgrounds(i, under[1]);
      if (useDouble_) {
        composite(list(one), orders[0].data(), length(one), under[0], out[0]);
        composite(list(i), orders[1].data(), length(i), under[1], out[1]);
      } else {
        compositePairBackToFront(list(one), orders[0].data(), length(one), under[0], out[0], list(i), orders[1].data(),
                                 length(i), under[1], out[1]);
      }
      store(one, out[0]), store(i, out[1]);
    }
    if (waiting >= 0) {
      orders[0].resize(length(waiting));
      b.depthOrder.sort(list(waiting), length(waiting), orders[0].data());
      glm::vec3 under[2], out[2];
      backgrounds(waiting, under);
      composite(list(waiting), orders[0].data(), length(waiting), under, out);
      store(waiting, out);
    }
    opaque.storeRow(y, b.columns.data(), resolved, b.resolved[0].data(), profile);
    analysis.storeRow(y, b.columns.data(), resolved, b.resolved[1].data(), profile);
  }
  // A band's store, kept between bands and frames: as many as bands drawn at once (one a worker).
  BandLists* takeBand() {
    const std::lock_guard<std::mutex> lock(bandsMutex_);
    if (spareBands_.empty()) return bands_.emplace_back(std::make_unique<BandLists>()).get();
    BandLists* b = spareBands_.back();
    spareBands_.pop_back();
    return b;
  }
  void giveBand(BandLists* b) {
    const std::lock_guard<std::mutex> lock(bandsMutex_);
    spareBands_.push_back(b);
  }

  static thread_local BandLists* currentBand;  // the band this worker is drawing
  bool useDouble_;
  bool keepLists_;
  uint64_t maxFragments_;
  std::vector<uint32_t> count_;  // each pixel's fragments, from the counting pass
  std::mutex bandsMutex_;
  std::vector<std::unique_ptr<BandLists>> bands_;
  std::vector<BandLists*> spareBands_;
};

thread_local BandLists* Abuffer::currentBand = nullptr;

}  // namespace

const MethodInfo& abufferInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "abuffer",
      "exact per-pixel sorted A-buffer (ground truth), OVER back to front",
      {{"precision", "float", "arithmetic of the OVER composite", {"float", "double"}},
       {"max_fragments", "50000000", "fragment budget (32 bytes each); exceeding it is an error", {},
        OptionNumber::integer(1, 0x1p40)},
       {"lists", "none", "whether the frame's result keeps every pixel's fragments (FrameResult::fragmentLists)",
        {"none", "keep"}}}};
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
