// DepthOrder's keys sorted in AVX-512 registers (depth_order_registers.h).
#include "methods/depth_order_registers.h"

#include <cstddef>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace oitref::methods {

#if defined(__x86_64__)
namespace {

// The network in the form whose comparators all put the smaller key at the lower position: for
// each block size S = 2, 4, … the "flip" step compares position e with S − 1 − e of its block, then
// half-cleaners compare e with e + S/4, e + S/8, … e + 1. Within a register each step is one lane
// permutation, a minimum, a maximum and a blend (the upper lanes of each pair take the maximum).
#define OITREF_AVX512 gnu::target("avx512f"), gnu::always_inline
typedef uint64_t Keys8 __attribute__((vector_size(64)));

[[OITREF_AVX512]] inline Keys8 smaller(Keys8 a, Keys8 b) { return a < b ? a : b; }
[[OITREF_AVX512]] inline Keys8 larger(Keys8 a, Keys8 b) { return a < b ? b : a; }
// Each lane compared with the lane that PARTNER names (eight lane numbers); the lanes that UPPER
// names from the second operand (lane numbers 8–15) keep the larger key.
#define OITREF_UNWRAP(...) __VA_ARGS__
#define OITREF_COMPARE_LANES(x, PARTNER, UPPER)                          \
  do {                                                                  \
    const Keys8 p = __builtin_shufflevector(x, x, OITREF_UNWRAP PARTNER); \
    x = __builtin_shufflevector(smaller(x, p), larger(x, p), UPPER);      \
  } while (0)
#define OITREF_PAIRS 1, 0, 3, 2, 5, 4, 7, 6
#define OITREF_PAIRS_UPPER 0, 9, 2, 11, 4, 13, 6, 15
#define OITREF_QUADS_UPPER 0, 1, 10, 11, 4, 5, 14, 15
#define OITREF_HALVES_UPPER 0, 1, 2, 3, 12, 13, 14, 15
#define OITREF_REVERSED 7, 6, 5, 4, 3, 2, 1, 0

[[OITREF_AVX512]] inline Keys8 reversed(Keys8 x) { return __builtin_shufflevector(x, x, OITREF_REVERSED); }

// The half-cleaners at distances 4, 2, 1 (a register whose keys form a bitonic sequence: sorted).
[[OITREF_AVX512]] inline Keys8 cleanRegister(Keys8 x) {
  OITREF_COMPARE_LANES(x, (4, 5, 6, 7, 0, 1, 2, 3), OITREF_HALVES_UPPER);
  OITREF_COMPARE_LANES(x, (2, 3, 0, 1, 6, 7, 4, 5), OITREF_QUADS_UPPER);
  OITREF_COMPARE_LANES(x, (OITREF_PAIRS), OITREF_PAIRS_UPPER);
  return x;
}
// One register's eight keys sorted: blocks of 2, 4 and 8.
[[OITREF_AVX512]] inline Keys8 sortRegister(Keys8 x) {
  OITREF_COMPARE_LANES(x, (OITREF_PAIRS), OITREF_PAIRS_UPPER);
  OITREF_COMPARE_LANES(x, (3, 2, 1, 0, 7, 6, 5, 4), OITREF_QUADS_UPPER);
  OITREF_COMPARE_LANES(x, (OITREF_PAIRS), OITREF_PAIRS_UPPER);
  OITREF_COMPARE_LANES(x, (OITREF_REVERSED), OITREF_HALVES_UPPER);
  OITREF_COMPARE_LANES(x, (2, 3, 0, 1, 6, 7, 4, 5), OITREF_QUADS_UPPER);
  OITREF_COMPARE_LANES(x, (OITREF_PAIRS), OITREF_PAIRS_UPPER);
  return x;
}

// How many of the eight list positions first … first + 7 lie before n.
[[OITREF_AVX512]] inline uint32_t listPositionsFrom(uint32_t first, uint32_t n) {
  return n > first ? (n - first < 8 ? n - first : 8) : 0;
}

// The keys of the eight fragments list[first, first + 8): the view depth's bits made to order as
// unsigned integers (+0 added first, so that −0 is +0) in the upper half, the list position in the
// lower; all ones for positions at n and past it (never read). nan: a view or window depth of
// these fragments is NaN.
[[OITREF_AVX512]] inline Keys8 fragmentKeys(const FragmentDepths* list, uint32_t first, uint32_t n, bool& nan) {
  static_assert(sizeof(FragmentDepths) == 8 && offsetof(FragmentDepths, windowDepth) == 0 &&
                offsetof(FragmentDepths, viewDepth) == 4);
  const uint32_t here = listPositionsFrom(first, n);
  const float* f = reinterpret_cast<const float*>(list + first);
  typedef float F16 __attribute__((vector_size(64)));
  typedef float F8 __attribute__((vector_size(32)));
  typedef int32_t I8 __attribute__((vector_size(32)));
  typedef uint32_t U8 __attribute__((vector_size(32)));
  // The eight fragments' depths in one line's worth: window depths in the even lanes, view depths
  // in the odd ones (past n, none read).
  F16 depths;
  if (here == 8) __builtin_memcpy(&depths, f, sizeof depths);
  else depths = F16(_mm512_maskz_loadu_ps(__mmask16((1u << (2 * here)) - 1), f));
  const F8 view = __builtin_shufflevector(depths, depths, 1, 3, 5, 7, 9, 11, 13, 15);
  const F8 window = __builtin_shufflevector(depths, depths, 0, 2, 4, 6, 8, 10, 12, 14);
  const I8 isNan = (view != view) | (window != window);
  nan |= _mm256_movemask_ps(__m256(isNan)) != 0;
  const U8 bits = U8(view + 0.0f);
  const U8 ordered = bits ^ (U8(I8(bits) >> 31) | 0x80000000u);
  const Keys8 lane = {0, 1, 2, 3, 4, 5, 6, 7};
  const Keys8 keys = __builtin_convertvector(ordered, Keys8) << 32 | (lane + first);
  return lane < here ? keys : ~Keys8{};
}

// The last stage of a bitonic sort of registers r[0, B) (B a power of two), whose halves r[0, B/2)
// and r[B/2, B) are each sorted: the flip step pairs register j with B − 1 − j, lane i with lane
// 7 − i; the half-cleaners pair whole registers at distances B/4 … 1, then each register's lanes.
// Only r[0, Real) need be there: the registers above them stand for the all-ones keys past a
// list's end, which no comparator moves (each pairs them with themselves or with a key that stays
// below), so the comparators that touch them are left out and they are never read or written (a
// list's last block of fewer keys: orderInWindow's lastShortBlock).
template <int B, int Real = B>
[[OITREF_AVX512]] inline void mergeHalves(Keys8* r) {
  for (int j = 0; j < B / 2; ++j) {
    if (B - 1 - j >= Real) continue;
    const Keys8 rb = reversed(r[B - 1 - j]), lo = smaller(r[j], rb), hi = larger(r[j], rb);
    r[j] = lo, r[B - 1 - j] = reversed(hi);
  }
  for (int D = B / 4; D >= 1; D /= 2)
    for (int j = 0; j < B; ++j)
      if ((j & D) == 0 && j + D < Real) {
        const Keys8 lo = smaller(r[j], r[j + D]), hi = larger(r[j], r[j + D]);
        r[j] = lo, r[j + D] = hi;
      }
  for (int j = 0; j < Real; ++j) r[j] = cleanRegister(r[j]);
}
// Registers r[0, M) sorted as one sequence of 8M keys: each register alone, then blocks of 2, 4 …
// M registers merged.
template <int M>
[[OITREF_AVX512]] inline void sortRegisters(Keys8* r) {
  for (int j = 0; j < M; ++j) r[j] = sortRegister(r[j]);
  if constexpr (M >= 2) {
    for (int block = 0; block < M; block += 2) mergeHalves<2>(r + block);
  }
  if constexpr (M >= 4) {
    for (int block = 0; block < M; block += 4) mergeHalves<4>(r + block);
  }
  static_assert(M <= 4);
}

// Sorted keys emitted at order[first, first + 8) (their list positions; none at n or past it);
// last: the key emitted before them, then their last. sorted: false once a key is smaller than
// the one before it; tie: true once two consecutive keys have equal view depths.
[[OITREF_AVX512]] inline void emit(Keys8 x, uint32_t first, uint32_t n, uint32_t* order, Keys8& last, bool& sorted, bool& tie) {
  const uint32_t here = listPositionsFrom(first, n);
  const __mmask8 valid = __mmask8((1u << here) - 1);
  _mm512_mask_cvtepi64_storeu_epi32(order + first, valid, __m512i(x));
  const Keys8 before = __builtin_shufflevector(last, x, 7, 8, 9, 10, 11, 12, 13, 14);  // each lane's predecessor
  sorted &= (_mm512_mask_cmplt_epu64_mask(valid, __m512i(x), __m512i(before)) == 0);
  tie |= (_mm512_mask_cmpeq_epu64_mask(valid, __m512i(x >> 32), __m512i(before >> 32)) & ~__mmask8(first == 0)) != 0;
  last = x;
}

// orderInWindow's last block when it holds K < M registers of keys (those from `first` on): merged
// with the window in fewer registers (mergeHalves over M + K of them), and everything emitted.
template <int M, int K>
[[OITREF_AVX512]] inline bool lastShortBlock(const FragmentDepths* list, uint32_t n, uint32_t first, Keys8* r, uint32_t* order,
                                             Keys8& last, bool& sorted, bool& tie, bool& nan) {
  for (int j = 0; j < K; ++j) r[M + j] = fragmentKeys(list, first + 8 * j, n, nan);
  sortRegisters<K>(r + M);
  mergeHalves<2 * M, M + K>(r);
  for (int j = 0; j < M + K; ++j) emit(r[j], first - 8 * M + 8 * j, n, order, last, sorted, tie);
  return sorted && !nan;
}

// The window: the 8M largest keys so far stay in registers, sorted. Each next block of 8M keys,
// sorted, is merged with them, and the lower 8M are emitted: final if no later key is smaller,
// which the emitted order's check finds out. A key with at most 8M larger keys before it never
// breaks that: when a key above it is emitted, the window holds 8M keys above that one.
template <int M>
[[gnu::target("avx512f")]] bool orderInWindow(const FragmentDepths* list, uint32_t n, uint32_t* order, bool& tie) {
  constexpr uint32_t W = 8 * M;
  Keys8 r[2 * M], last = {};
  bool nan = false, sorted = true;
  tie = false;
  for (int j = 0; j < M; ++j) r[j] = fragmentKeys(list, 8 * j, n, nan);
  sortRegisters<M>(r);
  for (uint32_t first = W; first < n; first += W) {
    if constexpr (M == 4) {
      // A last block of at most a quarter or half of W keys (dense's lists hold 71 fragments on
      // average: of a third block of 32, most is past the end).
      if (n - first <= 8) return lastShortBlock<M, 1>(list, n, first, r, order, last, sorted, tie, nan);
      if (n - first <= 16) return lastShortBlock<M, 2>(list, n, first, r, order, last, sorted, tie, nan);
    }
    for (int j = 0; j < M; ++j) r[M + j] = fragmentKeys(list, first + 8 * j, n, nan);
    sortRegisters<M>(r + M);
    mergeHalves<2 * M>(r);
    for (int j = 0; j < M; ++j) emit(r[j], first - W + 8 * j, n, order, last, sorted, tie), r[j] = r[M + j];
  }
  const uint32_t lastBlock = (n - 1) / W * W;
  for (int j = 0; j < M; ++j) emit(r[j], lastBlock + 8 * j, n, order, last, sorted, tie);
  return sorted && !nan;
}
#undef OITREF_AVX512
#undef OITREF_COMPARE_LANES
#undef OITREF_UNWRAP
#undef OITREF_PAIRS
#undef OITREF_PAIRS_UPPER
#undef OITREF_QUADS_UPPER
#undef OITREF_HALVES_UPPER
#undef OITREF_REVERSED

}  // namespace

bool registerOrderAvailable() {
  static const bool avx512 = __builtin_cpu_supports("avx512f");
  return avx512;
}

bool orderInRegisters(const FragmentDepths* list, uint32_t n, uint32_t* order, bool& tie) {
  if (n == 0 || !registerOrderAvailable()) return false;
  // A list that fits one window is sorted whole, in as few registers as hold it.
  if (n <= 8) return orderInWindow<1>(list, n, order, tie);
  if (n <= 16) return orderInWindow<2>(list, n, order, tie);
  return orderInWindow<4>(list, n, order, tie);
}
#else
bool registerOrderAvailable() { return false; }
bool orderInRegisters(const FragmentDepths*, uint32_t, uint32_t*, bool&) { return false; }
#endif

}  // namespace oitref::methods
