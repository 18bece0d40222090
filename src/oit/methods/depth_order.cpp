#include "methods/depth_order.h"

#include <algorithm>
#include <cmath>

#include "methods/depth_order_registers.h"

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

// Insertion by view depth alone over SoA keys (view and list position) with eight sentinel slots
// before position 0 (view −∞: nothing comes before them); equal view depths keep their list order
// (the insertion is stable) and DepthOrder::orderFromLaneKeys orders each run of them by window
// depth afterwards. The last eight sorted keys stay in registers: for position i, A holds positions
// i−8 … i−1 and B positions i−7 … i (the new key last); the new key goes c places back, where c
// counts the lanes of A it comes before (a run at the end, A being sorted). step(i) returns false
// when the moves exceed the budget (the keys are then a stable partial result). Each key's
// insertion waits for the one before (the registers): a chain of about eight cycles a key, which
// two lists inserted side by side (sortPair) overlap.
struct LaneInserter {
  float* v;
  uint32_t* ix;
  size_t budget, moves = 0;
  f8 rv;
  i8 ri;
  [[gnu::target("avx2,popcnt"), gnu::always_inline]] inline LaneInserter(float* v_, uint32_t* ix_, size_t budget_)
      : v(v_), ix(ix_), budget(budget_) {
    __builtin_memcpy(&rv, v - 8, 32);
    __builtin_memcpy(&ri, ix - 8, 32);
  }
  [[gnu::target("avx2,popcnt"), gnu::always_inline]] inline bool step(uint32_t i) {
    const float kv = v[i];
    const f8 sv = f8{} + kv;
    const i8 si = i8{} + int32_t(i);
    const i8 isBefore = sv < rv;
    const int c = __builtin_popcount(unsigned(_mm256_movemask_ps(__m256(isBefore))));
    if (c == 8) {  // further back than the registers reach: the scalar step in memory
      __builtin_memcpy(v + int64_t(i) - 8, &rv, 32);
      __builtin_memcpy(ix + int64_t(i) - 8, &ri, 32);
      int64_t j = i;
      for (; kv < v[j - 1]; --j) v[j] = v[j - 1], ix[j] = ix[j - 1];
      v[j] = kv, ix[j] = i;
      moves += size_t(int64_t(i) - j);
      __builtin_memcpy(&rv, v + int64_t(i) - 7, 32);
      __builtin_memcpy(&ri, ix + int64_t(i) - 7, 32);
      return moves <= budget;
    }
    moves += size_t(c);
    // The lanes that move are isBefore itself (a run at the end); the new key goes to the lane
    // just below them: each from the comparison, not from c, to keep the chain from one key to
    // the next short.
    // B from A: one lane down, the new key (or for `at`, all ones) into lane 7.
#define OITREF_NEXT_LANES 1, 2, 3, 4, 5, 6, 7, 8
    const i8 shifted = isBefore, at = __builtin_shufflevector(isBefore, i8{} - 1, OITREF_NEXT_LANES) & ~isBefore;
    const f8 bv = __builtin_shufflevector(rv, sv, OITREF_NEXT_LANES);
    const i8 bi = __builtin_shufflevector(ri, si, OITREF_NEXT_LANES);
#undef OITREF_NEXT_LANES
    rv = at ? sv : shifted ? rv : bv;
    ri = at ? si : shifted ? ri : bi;
    // Positions i−7 … i in memory too: the scalar step and the result read them.
    __builtin_memcpy(v + int64_t(i) - 7, &rv, 32);
    __builtin_memcpy(ix + int64_t(i) - 7, &ri, 32);
    return moves <= budget;
  }
};

// Keys [from, n) of one inserter; false when it exceeds its budget.
[[gnu::target("avx2,popcnt"), gnu::always_inline]] inline bool insertRest(LaneInserter& a, uint32_t from, uint32_t n) {
  for (uint32_t i = from; i < n; ++i)
    if (!a.step(i)) return false;
  return true;
}

// One list's keys (v, ix: past their eight sentinels) sorted; false when it exceeds its budget.
[[gnu::target("avx2,popcnt")]] bool insertInLanes(float* v, uint32_t* ix, uint32_t n) {
  LaneInserter a(v, ix, moveBudget(n));
  return insertRest(a, 0, n);
}

// Two lists' insertions side by side while both have keys (their chains overlap), then the
// longer one's rest. ok[k]: list k stayed within its budget.
[[gnu::target("avx2,popcnt")]] void insertTwoInLanes(float* va, uint32_t* ia, uint32_t na, float* vb, uint32_t* ib, uint32_t nb,
                                                     bool ok[2]) {
  LaneInserter a(va, ia, moveBudget(na)), b(vb, ib, moveBudget(nb));
  const uint32_t both = std::min(na, nb);
  uint32_t i = 0;
  bool okA = true, okB = true;
  for (; i < both && okA && okB; ++i) okA = a.step(i), okB = b.step(i);
  ok[0] = okA && insertRest(a, i, na);
  ok[1] = okB && insertRest(b, i, nb);
}
#endif

}  // namespace

// order (sorted by view depth, ties in list order) with each run of equal view depths (== : −0 and
// +0 too) put in the order of their window depths, ties still in list order: the order of `before`.
static void orderEqualViewRuns(const FragmentDepths* list, uint32_t n, uint32_t* order) {
  for (uint32_t a = 0; a + 1 < n;) {
    uint32_t b = a + 1;
    while (b < n && list[order[b]].viewDepth == list[order[a]].viewDepth) ++b;
    if (b - a > 1)
      std::stable_sort(order + a, order + b, [list](uint32_t x, uint32_t y) { return list[x].windowDepth < list[y].windowDepth; });
    a = b;
  }
}

void DepthOrder::orderFromKeys(uint32_t n, uint32_t* order, bool sorted) {
  if (!sorted)
    std::stable_sort(keys_.begin(), keys_.begin() + n, [](const Key& a, const Key& b) {
      return before(a.viewDepth, a.windowDepth, b.viewDepth, b.windowDepth);
    });
  for (uint32_t i = 0; i < n; ++i) order[i] = keys_[i].index;
}

void DepthOrder::sortScalar(const FragmentDepths* list, uint32_t n, uint32_t* order) {
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

bool DepthOrder::laneKeys(int k, const FragmentDepths* list, uint32_t n) {
  LaneKeys& keys = lanes_[k];
  keys.view.resize(8 + size_t(n)), keys.index.resize(8 + size_t(n));
  std::fill_n(keys.view.begin(), 8, -INFINITY), std::fill_n(keys.index.begin(), 8, 0);
  bool hasNan = false;
  for (uint32_t i = 0; i < n; ++i) {
    keys.view[8 + i] = list[i].viewDepth, keys.index[8 + i] = i;
    hasNan |= int(std::isnan(list[i].viewDepth)) | int(std::isnan(list[i].windowDepth));  // no branch per key
  }
  return !hasNan;
}

void DepthOrder::orderFromLaneKeys(int k, const FragmentDepths* list, uint32_t n, uint32_t* order, bool sorted) {
  const LaneKeys& keys = lanes_[k];
  if (sorted) {
    // Sorted by view depth, ties in list order: each run of equal view depths (== : −0 and +0
    // too) in the order of their window depths, ties still in list order: the order of `before`.
    const float* view = keys.view.data() + 8;
    std::copy_n(keys.index.data() + 8, n, order);
    bool tie = false;  // in lanes, no branch per key: most lists have none
    for (uint32_t i = 1; i < n; ++i) tie |= view[i] == view[i - 1];
    if (tie) orderEqualViewRuns(list, n, order);
    return;
  }
  // Not nearly sorted: std::stable_sort finishes from the partial order, which is stable (equal
  // view depths, and so equal keys, still in list order).
  keys_.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = keys.index[8 + i];
    keys_[i] = {keys.view[8 + i], list[j].windowDepth, j};
  }
  orderFromKeys(n, order, false);
}

bool DepthOrder::sortInRegisters(const FragmentDepths* list, uint32_t n, uint32_t* order) {
  bool tie = false;
  if (n < 2 || !orderInRegisters(list, n, order, tie)) return false;
  if (tie) orderEqualViewRuns(list, n, order);
  return true;
}

bool DepthOrder::lanesAvailable() {
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
  return avx2;
#else
  return false;
#endif
}

void DepthOrder::sort(const FragmentDepths* list, uint32_t n, uint32_t* order) {
  if (!sortInRegisters(list, n, order)) sortByInsertion(list, n, order);
}

void DepthOrder::sortByInsertion(const FragmentDepths* list, uint32_t n, uint32_t* order) {
#if defined(__x86_64__)
  if (lanesAvailable() && n > 1) {
    if (!laneKeys(0, list, n)) return sortScalar(list, n, order);
    LaneKeys& k = lanes_[0];
    return orderFromLaneKeys(0, list, n, order, insertInLanes(k.view.data() + 8, k.index.data() + 8, n));
  }
#endif
  sortScalar(list, n, order);
}

void DepthOrder::sortPair(const FragmentDepths* listA, uint32_t na, uint32_t* orderA, const FragmentDepths* listB,
                          uint32_t nb, uint32_t* orderB) {
  // A list that the registers' window sorts is done (the network has parallel work of its own);
  // two that it does not sort are inserted side by side.
  const bool doneA = sortInRegisters(listA, na, orderA), doneB = sortInRegisters(listB, nb, orderB);
  if (doneA || doneB) {
    if (!doneA) sortByInsertion(listA, na, orderA);
    if (!doneB) sortByInsertion(listB, nb, orderB);
    return;
  }
#if defined(__x86_64__)
  if (lanesAvailable() && na > 1 && nb > 1 && laneKeys(0, listA, na) && laneKeys(1, listB, nb)) {
    LaneKeys &a = lanes_[0], &b = lanes_[1];
    bool ok[2];
    insertTwoInLanes(a.view.data() + 8, a.index.data() + 8, na, b.view.data() + 8, b.index.data() + 8, nb, ok);
    orderFromLaneKeys(0, listA, na, orderA, ok[0]);
    orderFromLaneKeys(1, listB, nb, orderB, ok[1]);
    return;
  }
#endif
  sortByInsertion(listA, na, orderA);
  sortByInsertion(listB, nb, orderB);
}

}  // namespace oitref::methods
