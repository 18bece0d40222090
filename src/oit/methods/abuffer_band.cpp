// The A-buffer's bands (abuffer_band.h): their lists' layouts and their resolve.
#include "methods/abuffer_band.h"

#include <algorithm>
#include <cstring>
#include <utility>

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace oitref::methods {
namespace {

// v sized to n elements, its allocation exactly n where it grows (the memory checks count no
// more), its old elements not copied.
template <typename T>
void sizeExactly(std::vector<T>& v, size_t n) {
  if (v.size() >= n) return;
  v.clear();
  v.reserve(n);
  v.resize(n);
}

// OVER of one layer onto what lies behind it: c·α + C·(1 − α), each operation rounded in V — per
// channel (V = S = float or double) or per lane of a vector of floats (S = float).
template <typename V, typename S>
V over(V color, V alpha, V behind) {
  const V front = color * alpha, under = behind * (S(1) - alpha);
  return front + under;
}

// OVER back to front of the list's colours in `order` (front to back), onto both backgrounds.
template <typename Real>
void compositeBackToFront(const glm::vec4* list, const uint32_t* order, size_t n, const glm::vec3 background[2],
                          glm::vec3 result[2]) {
  Real c[2][3];
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) c[t][k] = Real(background[t][k]);
  for (size_t i = n; i-- > 0;) {
    const glm::vec4& color = list[order[i]];
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
void compositePairBackToFront(const glm::vec4* listA, const uint32_t* orderA, size_t na, const glm::vec3 backgroundA[2],
                              glm::vec3 resultA[2], const glm::vec4* listB, const uint32_t* orderB, size_t nb,
                              const glm::vec3 backgroundB[2], glm::vec3 resultB[2]) {
  FloatLanesOver a(backgroundA), b(backgroundB);
  size_t i = na, j = nb;
  for (; i > j; --i) a.layer(listA[orderA[i - 1]]);
  for (; j > i; --j) b.layer(listB[orderB[j - 1]]);
  for (; i > 0; --i, --j) a.layer(listA[orderA[i - 1]]), b.layer(listB[orderB[j - 1]]);
  a.finish(resultA);
  b.finish(resultB);
}

}  // namespace

size_t AbufferBand::beginLayout(const TileRect& r) {
  rect = r;
  width = r.x1 - r.x0;
  const size_t n = size_t(width) * size_t(r.y1 - r.y0);
  start.resize(n + 1);
  filled.assign(n, 0);
  return n;
}

void AbufferBand::layOutCounted(const TileRect& r, const uint32_t* count, int imageWidth, bool keepIds) {
  const size_t n = beginLayout(r);
  uint64_t at = 0;
  for (int y = r.y0, i = 0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x, ++i) start[size_t(i)] = at, at += count[size_t(y) * size_t(imageWidth) + size_t(x)];
  start[n] = at;
  sizeExactly(depths, at), sizeExactly(colors, at);
  withIds = keepIds;
  if (withIds) sizeExactly(ids, at);
}

void AbufferBand::layOutBounded(const TileRect& r, uint64_t bound) {
  const size_t n = beginLayout(r);
  const uint64_t stride = boundedStride(bound);
  for (size_t i = 0; i <= n; ++i) start[i] = i * stride;
  sizeExactly(depths, start[n]), sizeExactly(colors, start[n]);
  withIds = false;
}

void AbufferBand::shrinkTo(uint64_t records) {
  if (depths.capacity() > records) std::vector<FragmentDepths>().swap(depths);
  if (colors.capacity() > records) std::vector<glm::vec4>().swap(colors);
  if (ids.capacity() > records) std::vector<std::array<uint32_t, 2>>().swap(ids);
}

void AbufferBand::copyList(size_t i, TransparentFragment* out) const {
  for (uint64_t k = start[i], end = k + filled[i]; k < end; ++k, ++out)
    *out = {depths[k].windowDepth, depths[k].viewDepth, colors[k], ids[k][0], ids[k][1]};
}

void AbufferBand::resolveRow(int y, Image& opaque, Image& analysis, const Profile& profile, bool useDouble) {
  const size_t first = size_t(y - rect.y0) * size_t(width);
  const int n = width;
  const uint32_t* length = filled.data() + first;
  int withFragments = 0;
  for (int i = 0; i < n; ++i) withFragments += length[i] > 0;
  if (withFragments == 0) return;
  for (int t = 0; t < 2; ++t) {
    texels_[t].resize(size_t(n));
    (t == 0 ? opaque : analysis).fetchRun(y, rect.x0, n, texels_[t].data());
  }
  auto list = [&](int i) { return depths.data() + start[first + size_t(i)]; };
  auto colorsOf = [&](int i) { return colors.data() + start[first + size_t(i)]; };
  auto backgrounds = [&](int i, glm::vec3 out[2]) {
    out[0] = glm::vec3(texels_[0][size_t(i)]), out[1] = glm::vec3(texels_[1][size_t(i)]);
  };
  int resolved = 0;
  columns_.resize(size_t(withFragments)), resolved_[0].resize(size_t(withFragments)), resolved_[1].resize(size_t(withFragments));
  auto store = [&](int i, const glm::vec3 out[2]) {
    columns_[size_t(resolved)] = rect.x0 + i;
    for (int t = 0; t < 2; ++t) resolved_[t][size_t(resolved)] = glm::vec4(out[t], 1.0f);
    ++resolved;
  };
  const auto composite = useDouble ? compositeBackToFront<double> : compositeBackToFront<float>;
  // Two pixels at a time, side by side (DepthOrder::sortPair, compositePairBackToFront): each
  // insertion and each layer waits for the one before, and the other pixel's work fills that wait.
  int waiting = -1;  // a pixel whose list waits for a second one
  for (int i = 0; i < n; ++i) {
    if (length[i] == 0) continue;
    if (waiting < 0) {
      waiting = i;
      continue;
    }
    const int one = std::exchange(waiting, -1);
    orders_[0].resize(length[one]), orders_[1].resize(length[i]);
    depthOrder_.sortPair(list(one), length[one], orders_[0].data(), list(i), length[i], orders_[1].data());
    glm::vec3 under[2][2], out[2][2];
    backgrounds(one, under[0]), backgrounds(i, under[1]);
    if (useDouble) {
      composite(colorsOf(one), orders_[0].data(), length[one], under[0], out[0]);
      composite(colorsOf(i), orders_[1].data(), length[i], under[1], out[1]);
    } else {
      compositePairBackToFront(colorsOf(one), orders_[0].data(), length[one], under[0], out[0], colorsOf(i), orders_[1].data(),
                               length[i], under[1], out[1]);
    }
    store(one, out[0]), store(i, out[1]);
  }
  if (waiting >= 0) {
    orders_[0].resize(length[waiting]);
    depthOrder_.sort(list(waiting), length[waiting], orders_[0].data());
    glm::vec3 under[2], out[2];
    backgrounds(waiting, under);
    composite(colorsOf(waiting), orders_[0].data(), length[waiting], under, out);
    store(waiting, out);
  }
  opaque.storeRow(y, columns_.data(), resolved, resolved_[0].data(), profile);
  analysis.storeRow(y, columns_.data(), resolved, resolved_[1].data(), profile);
}

void AbufferBand::Tally::add(const Tally& o) {
  fragments += o.fragments, covered += o.covered;
  deepest = std::max(deepest, o.deepest);
}

AbufferBand::Tally AbufferBand::tally() const {
  Tally t;
  for (uint32_t n : filled) t.fragments += n, t.covered += n > 0, t.deepest = std::max(t.deepest, n);
  return t;
}

}  // namespace oitref::methods
