#include "pipeline/depth_batch.h"

#include <cstdint>
#include <cstring>

namespace oitref::detail {
namespace {

template <DepthFormat Format, CompareFunc Func, bool Write>
int testBatch(DepthBuffer& depth, int x, int y, const double* z, int n, int* passed) {
  using Word = std::conditional_t<Format == DepthFormat::D16, uint16_t, uint32_t>;
  Word* row = static_cast<Word*>(depth.texel(x, y));
  int count = 0, i = 0;
  for (; i + 4 <= n; i += 4) {
    lanes::d4 z4;
    std::memcpy(&z4, z + i, sizeof z4);
    const lanes::u4 fragment = encodeDepthAs<Format>(z4);
    lanes::u4 stored;
    if constexpr (Format == DepthFormat::D16) stored = lanes::u4{row[i], row[i + 1], row[i + 2], row[i + 3]};
    else std::memcpy(&stored, row + i, sizeof stored);
    const lanes::i4 pass = depthTestPassesAs<Func, Format>(fragment, stored);
    if constexpr (Write) {
      // The old value stored back where the test fails: the four pixels are distinct.
      const lanes::u4 result = pass ? fragment : stored;
      if constexpr (Format == DepthFormat::D16)
        for (int l = 0; l < 4; ++l) row[i + l] = Word(result[l]);
      else std::memcpy(row + i, &result, sizeof result);
    }
    for (int l = 0; l < 4; ++l) {
      passed[count] = i + l;
      count += pass[l] & 1;
    }
  }
  for (; i < n; ++i) {
    const uint32_t fragment = encodeDepthAs<Format>(z[i]), stored = row[i];
    const bool pass = depthTestPassesAs<Func, Format>(fragment, stored);
    if constexpr (Write) row[i] = Word(pass ? fragment : stored);
    passed[count] = i;
    count += pass;
  }
  return count;
}

template <DepthFormat Format, bool Write>
DepthBatchTest forFunc(CompareFunc func) {
  switch (func) {
    case CompareFunc::Never: return testBatch<Format, CompareFunc::Never, Write>;
    case CompareFunc::Less: return testBatch<Format, CompareFunc::Less, Write>;
    case CompareFunc::Equal: return testBatch<Format, CompareFunc::Equal, Write>;
    case CompareFunc::LEqual: return testBatch<Format, CompareFunc::LEqual, Write>;
    case CompareFunc::Greater: return testBatch<Format, CompareFunc::Greater, Write>;
    case CompareFunc::NotEqual: return testBatch<Format, CompareFunc::NotEqual, Write>;
    case CompareFunc::GEqual: return testBatch<Format, CompareFunc::GEqual, Write>;
    case CompareFunc::Always: break;
  }
  return testBatch<Format, CompareFunc::Always, Write>;
}

template <DepthFormat Format>
DepthBatchTest forWrite(CompareFunc func, bool writeMask) {
  return writeMask ? forFunc<Format, true>(func) : forFunc<Format, false>(func);
}

}  // namespace

DepthBatchTest depthBatchTest(DepthFormat format, CompareFunc func, bool writeMask) {
  switch (format) {
    case DepthFormat::D16: return forWrite<DepthFormat::D16>(func, writeMask);
    case DepthFormat::D24: return forWrite<DepthFormat::D24>(func, writeMask);
    case DepthFormat::D32F: break;
  }
  return forWrite<DepthFormat::D32F>(func, writeMask);
}

}  // namespace oitref::detail
