#include "pipeline/depth_batch.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace oitref::detail {
namespace {

// Left-packing: for each 4-bit mask of passing lanes, their indices in ascending order (the rest
// of the row is written but not counted). One vector store per four pixels instead of a chain of
// scalar extracts and adds.
struct LeftPack {
  alignas(16) int32_t lanes[16][4] = {};
  int32_t count[16] = {};  // the lanes set (no popcnt instruction in the portable build)
  constexpr LeftPack() {
    for (int m = 0; m < 16; ++m)
      for (int l = 0; l < 4; ++l)
        if (m >> l & 1) lanes[m][count[m]++] = l;
  }
};
constexpr LeftPack kLeftPack;

// Bit l set where lane l of the comparison's result (−1/0) is set.
inline int laneMask(lanes::i4 pass) {
#if defined(__SSE2__)
  return _mm_movemask_ps(_mm_castsi128_ps(__m128i(pass)));
#else
  return (pass[0] & 1) | (pass[1] & 2) | (pass[2] & 4) | (pass[3] & 8);
#endif
}

template <DepthFormat Format, CompareFunc Func, bool Write, UnormRounding Rounding, bool Fetched = false>
int testBatch(DepthBuffer& depth, int x, int y, const double* z, int n, int* passed) {
  // Fetched: a shader's test against the stored depths as llvmpipe's texelFetch returns them
  // (depthCodeAsFetched); such a test never writes.
  static_assert(!(Fetched && Write));
  constexpr double maxCode = depthMaxCode(Format);
  using Word = std::conditional_t<Format == DepthFormat::D16, uint16_t, uint32_t>;
  Word* row = static_cast<Word*>(depth.texel(x, y));
  int count = 0, i = 0;
  for (; i + 4 <= n; i += 4) {
    lanes::d4 z4;
    std::memcpy(&z4, z + i, sizeof z4);
    const lanes::u4 fragment = encodeDepthAs<Format, lanes::d4, Rounding>(z4);
    lanes::u4 stored;
    if constexpr (Format == DepthFormat::D16) stored = lanes::u4{row[i], row[i + 1], row[i + 2], row[i + 3]};
    else std::memcpy(&stored, row + i, sizeof stored);
    const lanes::i4 pass = depthTestPassesAs<Func, Format>(fragment, Fetched ? llvmpipeDepthCodeAsFetched(stored, maxCode) : stored);
    if constexpr (Write) {
      // The old value stored back where the test fails: the four pixels are distinct.
      const lanes::u4 result = pass ? fragment : stored;
      if constexpr (Format == DepthFormat::D16)
        for (int l = 0; l < 4; ++l) row[i + l] = Word(result[l]);
      else std::memcpy(row + i, &result, sizeof result);
    }
    // passed has room: count ≤ i and i + 4 ≤ n.
    const int mask = laneMask(pass);
    lanes::i4 index;
    std::memcpy(&index, kLeftPack.lanes[mask], sizeof index);
    index += i;
    std::memcpy(passed + count, &index, sizeof index);
    count += kLeftPack.count[mask];
  }
  for (; i < n; ++i) {
    const uint32_t fragment = encodeDepthAs<Format, double, Rounding>(z[i]), stored = row[i];
    const bool pass = depthTestPassesAs<Func, Format>(fragment, Fetched ? llvmpipeDepthCodeAsFetched(stored, maxCode) : stored);
    if constexpr (Write) row[i] = Word(pass ? fragment : stored);
    passed[count] = i;
    count += pass;
  }
  return count;
}

// Whether every pixel of the run gives the test result `Passes` for every window z in
// [zLow, zHigh]: the depth codes are monotone in z, so the bound's code nearest to the other
// result stands for all (zLow's for less and lequal when rejecting, zHigh's when accepting, and
// the reverse for greater and gequal). ALWAYS passes everything.
// The code that stands for every window z in [zLow, zHigh] when asking whether all give the
// result `Passes`: the one nearest to the other result (runAll, rangeVerdict).
template <DepthFormat Format, CompareFunc Func, bool Passes>
uint32_t standingCode(double zLow, double zHigh) {
  constexpr bool nearer = Func == CompareFunc::Less || Func == CompareFunc::LEqual;
  return encodeDepthAs<Format>(nearer != Passes ? zLow : zHigh);
}

template <DepthFormat Format, CompareFunc Func, bool Passes>
bool runAll(const DepthBuffer& depth, int x, int y, int n, double zLow, double zHigh) {
  using Word = std::conditional_t<Format == DepthFormat::D16, uint16_t, uint32_t>;
  if constexpr (Func == CompareFunc::Always) return Passes;
  const uint32_t code = standingCode<Format, Func, Passes>(zLow, zHigh);
  const Word* row = static_cast<const Word*>(depth.texel(x, y));
  const lanes::u4 codes = lanes::u4{} + code;
  const lanes::i4 wanted = Passes ? lanes::i4{} - 1 : lanes::i4{};
  lanes::i4 other = {};  // lanes whose result was not the wanted one
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    lanes::u4 stored;
    if constexpr (Format == DepthFormat::D16) stored = lanes::u4{row[i], row[i + 1], row[i + 2], row[i + 3]};
    else std::memcpy(&stored, row + i, sizeof stored);
    other |= depthTestPassesAs<Func, Format>(codes, stored) ^ wanted;
  }
  if (laneMask(other)) return false;
  for (; i < n; ++i)
    if (depthTestPassesAs<Func, Format>(code, uint32_t(row[i])) != Passes) return false;
  return true;
}

template <DepthFormat Format, CompareFunc Func>
RunVerdict rangeVerdict(const StoredDepthRange& range, double zLow, double zHigh) {
  if (!range.ordered) return RunVerdict::Undecided;
  if constexpr (Func == CompareFunc::Always) return RunVerdict::AllPass;
  // Against the stored value nearest to the other result too: the least for less and lequal
  // when all pass, the greatest when all fail, and the reverse for greater and gequal.
  constexpr bool nearer = Func == CompareFunc::Less || Func == CompareFunc::LEqual;
  const uint32_t passing = standingCode<Format, Func, true>(zLow, zHigh);
  if (depthTestPassesAs<Func, Format>(passing, nearer ? range.least : range.greatest)) return RunVerdict::AllPass;
  const uint32_t failing = standingCode<Format, Func, false>(zLow, zHigh);
  if (!depthTestPassesAs<Func, Format>(failing, nearer ? range.greatest : range.least)) return RunVerdict::AllFail;
  return RunVerdict::Undecided;
}

template <DepthFormat Format>
DepthRangeVerdict rangeVerdictFor(CompareFunc func) {
  switch (func) {
    case CompareFunc::Less: return rangeVerdict<Format, CompareFunc::Less>;
    case CompareFunc::LEqual: return rangeVerdict<Format, CompareFunc::LEqual>;
    case CompareFunc::Greater: return rangeVerdict<Format, CompareFunc::Greater>;
    case CompareFunc::GEqual: return rangeVerdict<Format, CompareFunc::GEqual>;
    case CompareFunc::Always: return rangeVerdict<Format, CompareFunc::Always>;
    default: return nullptr;
  }
}

template <typename Word>
void leastAndGreatest(const Word* row, int n, uint32_t& least, uint32_t& greatest) {
  Word lo = row[0], hi = row[0];
  for (int i = 1; i < n; ++i) lo = std::min(lo, row[i]), hi = std::max(hi, row[i]);
  least = lo, greatest = hi;
}

template <DepthFormat Format>
DepthRunAccepts runAcceptsFor(CompareFunc func) {
  switch (func) {
    case CompareFunc::Less: return runAll<Format, CompareFunc::Less, true>;
    case CompareFunc::LEqual: return runAll<Format, CompareFunc::LEqual, true>;
    case CompareFunc::Greater: return runAll<Format, CompareFunc::Greater, true>;
    case CompareFunc::GEqual: return runAll<Format, CompareFunc::GEqual, true>;
    case CompareFunc::Always: return runAll<Format, CompareFunc::Always, true>;
    default: return nullptr;
  }
}

template <DepthFormat Format>
DepthRunRejects runRejectsFor(CompareFunc func) {
  switch (func) {
    case CompareFunc::Less: return runAll<Format, CompareFunc::Less, false>;
    case CompareFunc::LEqual: return runAll<Format, CompareFunc::LEqual, false>;
    case CompareFunc::Greater: return runAll<Format, CompareFunc::Greater, false>;
    case CompareFunc::GEqual: return runAll<Format, CompareFunc::GEqual, false>;
    default: return nullptr;
  }
}

template <DepthFormat Format, bool Write, UnormRounding Rounding>
DepthBatchTest forFunc(CompareFunc func) {
  switch (func) {
    case CompareFunc::Never: return testBatch<Format, CompareFunc::Never, Write, Rounding>;
    case CompareFunc::Less: return testBatch<Format, CompareFunc::Less, Write, Rounding>;
    case CompareFunc::Equal: return testBatch<Format, CompareFunc::Equal, Write, Rounding>;
    case CompareFunc::LEqual: return testBatch<Format, CompareFunc::LEqual, Write, Rounding>;
    case CompareFunc::Greater: return testBatch<Format, CompareFunc::Greater, Write, Rounding>;
    case CompareFunc::NotEqual: return testBatch<Format, CompareFunc::NotEqual, Write, Rounding>;
    case CompareFunc::GEqual: return testBatch<Format, CompareFunc::GEqual, Write, Rounding>;
    case CompareFunc::Always: break;
  }
  return testBatch<Format, CompareFunc::Always, Write, Rounding>;
}

template <DepthFormat Format, UnormRounding Rounding = UnormRounding::ExactNearestEven>
DepthBatchTest forWrite(CompareFunc func, bool writeMask) {
  return writeMask ? forFunc<Format, true, Rounding>(func) : forFunc<Format, false, Rounding>(func);
}

}  // namespace

DepthBatchTest depthBatchTest(DepthFormat format, CompareFunc func, bool writeMask, UnormRounding rounding) {
  const bool fp32 = rounding == UnormRounding::Fp32Product;
  switch (format) {
    case DepthFormat::D16:
      return fp32 ? forWrite<DepthFormat::D16, UnormRounding::Fp32Product>(func, writeMask)
                  : forWrite<DepthFormat::D16>(func, writeMask);
    case DepthFormat::D24:
      return fp32 ? forWrite<DepthFormat::D24, UnormRounding::Fp32Product>(func, writeMask)
                  : forWrite<DepthFormat::D24>(func, writeMask);
    case DepthFormat::D32F: break;
  }
  return forWrite<DepthFormat::D32F>(func, writeMask);
}

namespace {

template <DepthFormat Format>
DepthBatchTest fetchedFor(CompareFunc func) {
  constexpr UnormRounding E = UnormRounding::ExactNearestEven;
  switch (func) {
    case CompareFunc::Never: return testBatch<Format, CompareFunc::Never, false, E, true>;
    case CompareFunc::Less: return testBatch<Format, CompareFunc::Less, false, E, true>;
    case CompareFunc::Equal: return testBatch<Format, CompareFunc::Equal, false, E, true>;
    case CompareFunc::LEqual: return testBatch<Format, CompareFunc::LEqual, false, E, true>;
    case CompareFunc::Greater: return testBatch<Format, CompareFunc::Greater, false, E, true>;
    case CompareFunc::NotEqual: return testBatch<Format, CompareFunc::NotEqual, false, E, true>;
    case CompareFunc::GEqual: return testBatch<Format, CompareFunc::GEqual, false, E, true>;
    case CompareFunc::Always: break;
  }
  return testBatch<Format, CompareFunc::Always, false, E, true>;
}

}  // namespace

DepthBatchTest shaderDepthBatchTest(DepthFormat format, CompareFunc func, TextureFiltering read) {
  if (read != TextureFiltering::Llvmpipe || format == DepthFormat::D32F) return depthBatchTest(format, func, false);
  return format == DepthFormat::D16 ? fetchedFor<DepthFormat::D16>(func) : fetchedFor<DepthFormat::D24>(func);
}

DepthRunRejects depthRunRejects(DepthFormat format, CompareFunc func) {
  switch (format) {
    case DepthFormat::D16: return runRejectsFor<DepthFormat::D16>(func);
    case DepthFormat::D24: return runRejectsFor<DepthFormat::D24>(func);
    case DepthFormat::D32F: break;
  }
  return runRejectsFor<DepthFormat::D32F>(func);
}

DepthRunAccepts depthRunAccepts(DepthFormat format, CompareFunc func) {
  switch (format) {
    case DepthFormat::D16: return runAcceptsFor<DepthFormat::D16>(func);
    case DepthFormat::D24: return runAcceptsFor<DepthFormat::D24>(func);
    case DepthFormat::D32F: break;
  }
  return runAcceptsFor<DepthFormat::D32F>(func);
}

StoredDepthRange storedDepthRange(const DepthBuffer& depth, int x, int y, int n) {
  StoredDepthRange r;
  if (n <= 0) return r;
  if (depth.format() == DepthFormat::D16) leastAndGreatest(static_cast<const uint16_t*>(depth.texel(x, y)), n, r.least, r.greatest);
  else leastAndGreatest(static_cast<const uint32_t*>(depth.texel(x, y)), n, r.least, r.greatest);
  // fp32 values in [+0, 1] order like their bits (depthTestPassesAs compares them as floats).
  r.ordered = depth.format() != DepthFormat::D32F || r.greatest <= 0x3f800000u;
  return r;
}

DepthRangeVerdict depthRangeVerdict(DepthFormat format, CompareFunc func) {
  switch (format) {
    case DepthFormat::D16: return rangeVerdictFor<DepthFormat::D16>(func);
    case DepthFormat::D24: return rangeVerdictFor<DepthFormat::D24>(func);
    case DepthFormat::D32F: break;
  }
  return rangeVerdictFor<DepthFormat::D32F>(func);
}

}  // namespace oitref::detail
