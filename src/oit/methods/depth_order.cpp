#include "methods/depth_order.h"

#include <algorithm>
#include <cmath>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace oitref::methods {
namespace {

bool before(float viewA, float windowA, float viewB, float windowB) {
  return viewA != viewB ? viewA < viewB : windowA < windowB;
}
size_t moveBudget(uint32_t n) { return 8 * size_t(n) + 64; }

#if defined(__x86_64__)
typedef float f8 __attribute__((vector_size(32)));
typedef int32_t i8 __attribute__((vector_size(32)));

// Insertion over SoA keys with eight sentinel slots before position 0 (view and window −∞:
// nothing comes before them). The last eight sorted keys stay in registers: for position i, A
// holds positions i−8 … i−1 and B positions i−7 … i (the new key last); the new key goes c places
// back, where c counts the lanes of A it comes before (a run at the end, A being sorted). Returns
// false when the moves exceed the budget (the keys are then a stable partial result).
[[gnu::target("avx2,popcnt")]] bool insertInLanes(float* v, float* w, uint32_t* ix, uint32_t n, size_t budget) {
  f8 rv, rw;
  i8 ri;
  __builtin_memcpy(&rv, v - 8, 32);
  __builtin_memcpy(&rw, w - 8, 32);
  __builtin_memcpy(&ri, ix - 8, 32);
  size_t moves = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float kv = v[i], kw = w[i];
    const f8 sv = f8{} + kv, sw = f8{} + kw;
    const i8 si = i8{} + int32_t(i);
    const i8 isBefore = (sv < rv) | ((sv == rv) & (sw < rw));
    const int c = __builtin_popcount(unsigned(_mm256_movemask_ps(__m256(isBefore))));
    if (c == 8) {  // further back than the registers reach: the scalar step in memory
      __builtin_memcpy(v + int64_t(i) - 8, &rv, 32);
      __builtin_memcpy(w + int64_t(i) - 8, &rw, 32);
      __builtin_memcpy(ix + int64_t(i) - 8, &ri, 32);
      int64_t j = i;
      for (; before(kv, kw, v[j - 1], w[j - 1]); --j) v[j] = v[j - 1], w[j] = w[j - 1], ix[j] = ix[j - 1];
      v[j] = kv, w[j] = kw, ix[j] = i;
      moves += size_t(int64_t(i) - j);
      if (moves > budget) return false;
      __builtin_memcpy(&rv, v + int64_t(i) - 7, 32);
      __builtin_memcpy(&rw, w + int64_t(i) - 7, 32);
      __builtin_memcpy(&ri, ix + int64_t(i) - 7, 32);
      continue;
    }
    moves += size_t(c);
    // The lanes that move are isBefore itself (a run at the end); the new key goes to the lane
    // just below them: each from the comparison, not from c, to keep the chain from one key to
    // the next short.
    // B from A: one lane down, the new key (or for `at`, all ones) into lane 7.
#define OITREF_NEXT_LANES 1, 2, 3, 4, 5, 6, 7, 8
    const i8 shifted = isBefore, at = __builtin_shufflevector(isBefore, i8{} - 1, OITREF_NEXT_LANES) & ~isBefore;
    const f8 bv = __builtin_shufflevector(rv, sv, OITREF_NEXT_LANES), bw = __builtin_shufflevector(rw, sw, OITREF_NEXT_LANES);
    const i8 bi = __builtin_shufflevector(ri, si, OITREF_NEXT_LANES);
#undef OITREF_NEXT_LANES
    rv = at ? sv : shifted ? rv : bv;
    rw = at ? sw : shifted ? rw : bw;
    ri = at ? si : shifted ? ri : bi;
    // Positions i−7 … i in memory too: the scalar step and the result read them.
    __builtin_memcpy(v + int64_t(i) - 7, &rv, 32);
    __builtin_memcpy(w + int64_t(i) - 7, &rw, 32);
    __builtin_memcpy(ix + int64_t(i) - 7, &ri, 32);
    if (moves > budget) return false;
  }
  return true;
}
#endif

}  // namespace

void DepthOrder::orderFromKeys(uint32_t n, uint32_t* order, bool sorted) {
  if (!sorted)
    std::stable_sort(keys_.begin(), keys_.begin() + n, [](const Key& a, const Key& b) {
      return before(a.viewDepth, a.windowDepth, b.viewDepth, b.windowDepth);
    });
  for (uint32_t i = 0; i < n; ++i) order[i] = keys_[i].index;
}

void DepthOrder::sortScalar(const TransparentFragment* list, uint32_t n, uint32_t* order) {
  keys_.resize(n);
  for (uint32_t i = 0; i < n; ++i) keys_[i] = {list[i].viewDepth, list[i].windowDepth, i};
  size_t moves = 0;
  const size_t budget = moveBudget(n);
  for (uint32_t i = 1; i < n; ++i) {
    const Key k = keys_[i];
    uint32_t j = i;
    for (; j > 0 && before(k.viewDepth, k.windowDepth, keys_[j - 1].viewDepth, keys_[j - 1].windowDepth); --j)
      keys_[j] = keys_[j - 1];
    keys_[j] = k;
    moves += i - j;
    if (moves > budget) return orderFromKeys(n, order, false);
  }
  orderFromKeys(n, order, true);
}

void DepthOrder::sort(const TransparentFragment* list, uint32_t n, uint32_t* order) {
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
  if (avx2 && n > 1) {
    view_.resize(8 + size_t(n)), window_.resize(8 + size_t(n)), index_.resize(8 + size_t(n));
    std::fill_n(view_.begin(), 8, -INFINITY), std::fill_n(window_.begin(), 8, -INFINITY), std::fill_n(index_.begin(), 8, 0);
    bool hasNan = false;
    for (uint32_t i = 0; i < n; ++i) {
      view_[8 + i] = list[i].viewDepth, window_[8 + i] = list[i].windowDepth, index_[8 + i] = i;
      hasNan |= std::isnan(list[i].viewDepth) | std::isnan(list[i].windowDepth);
    }
    if (hasNan) return sortScalar(list, n, order);
    if (insertInLanes(view_.data() + 8, window_.data() + 8, index_.data() + 8, n, moveBudget(n))) {
      std::copy_n(index_.data() + 8, n, order);
      return;
    }
    // Not nearly sorted: std::stable_sort finishes from the stable partial order.
    keys_.resize(n);
    for (uint32_t i = 0; i < n; ++i) keys_[i] = {view_[8 + i], window_[8 + i], index_[8 + i]};
    return orderFromKeys(n, order, false);
  }
#endif
  sortScalar(list, n, order);
}

}  // namespace oitref::methods
