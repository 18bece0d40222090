// The exact per-pixel sorted A-buffer: every transparent fragment that passes the opaque depth
// test is stored per pixel — window depth, view depth, straight RGBA in fp32, object and
// primitive id — then sorted front to back by view depth (window depth, then submission order,
// break ties: the sort is stable over fragments stored in submission order), and composited back
// to front with OVER, C = c·α + C·(1 − α), in fp32 or (precision=double) in double.
//
// Storage is built as a GPU A-buffer with a prefix sum would: a counting pass, a check against
// the `max_fragments` budget (an error naming the deepest pixel, never an out-of-memory kill),
// then a storing pass. Each tile's pixels belong to one worker, so the per-pixel writes of the
// fragment shader are race-free and in submission order.
#include <algorithm>
#include <atomic>
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

class Abuffer final : public Method {
 public:
  explicit Abuffer(const MethodOptions& o)
      : useDouble_(o.is("precision", "double")), maxFragments_(uint64_t(o.number("max_fragments"))) {}
  const MethodInfo& info() const override { return abufferInfo(); }
  std::vector<AttachmentDecl> attachments() const override { return AttachmentList().declared(); }
  // The frame's own buffers, and the fragments that the geometry alone shows it must store
  // (fragment_bound.h): a frame that cannot fit is refused before anything is allocated. The
  // fragments themselves are counted, and checked again, by the counting pass.
  std::vector<MemoryItem> memoryNeed(int width, int height, const SceneGeometry& geometry) const override {
    std::vector<MemoryItem> items = frameBuffers(width, height, geometry);
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
    // that fits is never stopped.
    uint64_t known = 0;
    for (const MemoryItem& i : frameBuffers(w, h, context.geometry)) known += i.bytes;
    const uint64_t spare = context.memoryLimit > known ? context.memoryLimit - known : 0;
    const uint64_t fitting = std::min(maxFragments_, spare / sizeof(StoredFragment));
    std::vector<uint32_t> count(pixels, 0);
    std::atomic<uint64_t> counted{0};
    const uint64_t frameId = nextFrameId();
    bool stopped = false;
    try {
      run.transparentPositionPass("count", depthOnly, st, [&](const FragmentBatch& in, FragmentBatchOutput&) {
        uint32_t* row = count.data() + size_t(in.y) * w;
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
    const uint64_t total = std::accumulate(count.begin(), count.end(), uint64_t(0));
    const size_t deepest = size_t(std::max_element(count.begin(), count.end()) - count.begin());
    const std::string deepestText = "; the deepest pixel (" + std::to_string(deepest % w) + "," + std::to_string(deepest / w) +
                                    ") has " + std::to_string(count[deepest]) + " layers.";
    const uint64_t fragmentBytes = total * sizeof(StoredFragment);
    if (known + fragmentBytes > context.memoryLimit)
      throw std::runtime_error("A-buffer: " + std::to_string(total) + " fragments need " + formatBytes(fragmentBytes) +
                               " (plus " + formatBytes(known) + " for the frame), above the memory limit of " +
                               formatBytes(context.memoryLimit) + deepestText + " Render smaller or raise --memory-limit.");
    if (total > maxFragments_)
      throw std::runtime_error("A-buffer: " + std::to_string(total) + " fragments exceed max_fragments=" +
                               std::to_string(maxFragments_) + " (" + std::to_string(total * sizeof(StoredFragment) >> 20) +
                               " MiB)" + deepestText + " Raise it with --set max_fragments=N or render smaller.");
    std::vector<uint64_t> start(pixels + 1, 0);
    for (size_t p = 0; p < pixels; ++p) start[p + 1] = start[p] + count[p];
    std::vector<StoredFragment> fragments;
    if (context.pool) {
      fragments = context.pool->takeFragments(total);
    } else {
      util::reserveOnHugePages(fragments, total);
      fragments.resize(total);
    }
    std::vector<uint32_t> filled(pixels, 0);
    run.transparentBatchPass("store", depthOnly, st, [&](const FragmentBatch& in, const glm::vec4* c, FragmentBatchOutput&) {
      const size_t row = size_t(in.y) * w;
      for (int i = 0; i < in.count; ++i) {
        const size_t p = row + in.x[i];
        const uint64_t slot = start[p] + filled[p]++;
        fragments[slot] = {in.depth[i], in.viewDepth[i], c[i], in.drawId, in.primitiveId};
        // The line of the pixel's fragment after next, fetched now for writing: the pixel's next
        // fragment comes with a later primitive, and its write would otherwise wait on memory.
        if (slot + 2 < total) __builtin_prefetch(&fragments[slot + 2], 1);
      }
    });

    const bool useDouble = useDouble_;
    const auto composite = useDouble ? compositeBackToFront<double> : compositeBackToFront<float>;
    run.compositeOntoBackgroundsBatch(t, "sort+composite", [&](const FragmentBatch& in, const glm::vec3* const background[2],
                                                               glm::vec3* const result[2], bool* resolved) {
      // The stored lists stay in submission order for the result; the resolve sorts positions.
      // Two pixels at a time, side by side (DepthOrder::sortPair, compositePairBackToFront): each
      // insertion and each layer waits for the one before, and the other pixel's work fills that
      // wait.
      thread_local DepthOrder depthOrder;
      thread_local std::vector<uint32_t> orders[2];
      const size_t row = size_t(in.y) * w;
      auto list = [&](int i) { return fragments.data() + start[row + size_t(in.x[i])]; };
      auto length = [&](int i) { return count[row + size_t(in.x[i])]; };
      auto backgrounds = [&](int i, glm::vec3 out[2]) { out[0] = background[0][i], out[1] = background[1][i]; };
      auto store = [&](int i, const glm::vec3 out[2]) { result[0][i] = out[0], result[1][i] = out[1]; };
      int waiting = -1;  // a pixel whose list waits for a second one
      for (int i = 0; i < in.count; ++i) {
        resolved[i] = length(i) > 0;
        if (!resolved[i]) continue;
        if (waiting < 0) {
          waiting = i;
          continue;
        }
        const int first = std::exchange(waiting, -1);
        orders[0].resize(length(first)), orders[1].resize(length(i));
        depthOrder.sortPair(list(first), length(first), orders[0].data(), list(i), length(i), orders[1].data());
        glm::vec3 under[2][2], out[2][2];
        backgrounds(first, under[0]), backgrounds(i, under[1]);
        if (useDouble) {
          composite(list(first), orders[0].data(), length(first), under[0], out[0]);
          composite(list(i), orders[1].data(), length(i), under[1], out[1]);
        } else {
          compositePairBackToFront(list(first), orders[0].data(), length(first), under[0], out[0], list(i), orders[1].data(),
                                   length(i), under[1], out[1]);
        }
        store(first, out[0]), store(i, out[1]);
      }
      if (waiting >= 0) {
        orders[0].resize(length(waiting));
        depthOrder.sort(list(waiting), length(waiting), orders[0].data());
        glm::vec3 under[2], out[2];
        backgrounds(waiting, under);
        composite(list(waiting), orders[0].data(), length(waiting), under, out);
        store(waiting, out);
      }
    });

    uint64_t covered = 0;
    for (uint32_t c : count) covered += c > 0;
    result.stats.fragments = total;
    result.stats.depthComplexityMax = count[deepest];
    result.stats.depthComplexityMean = double(total) / double(pixels);
    result.stats.pixelsWithTransparency = covered;
    result.stats.fragmentStorageBytes = total * sizeof(StoredFragment) + (pixels + 1) * sizeof(uint64_t);
    t.finish(result, AttachmentList::kOpaque);
    result.fragmentLists = {context.width, context.height, std::move(start), std::move(fragments)};
    return result;
  }

 private:
  // The attachments and copies of every method, and the lists' heads.
  std::vector<MemoryItem> frameBuffers(int width, int height, const SceneGeometry& geometry) const {
    std::vector<MemoryItem> items = Method::memoryNeed(width, height, geometry);
    items.push_back({"fragment counts, offsets and fill levels (16 B/pixel)", uint64_t(width) * uint64_t(height) * 16});
    return items;
  }
  bool useDouble_;
  uint64_t maxFragments_;
};

}  // namespace

const MethodInfo& abufferInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "abuffer",
      "exact per-pixel sorted A-buffer (ground truth), OVER back to front",
      {{"precision", "float", "arithmetic of the OVER composite", {"float", "double"}},
       {"max_fragments", "50000000", "fragment budget (32 bytes each); exceeding it is an error", {},
        OptionNumber::integer(1, 0x1p40)}}};
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
