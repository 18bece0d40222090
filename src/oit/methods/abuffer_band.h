// The A-buffer's lists of one band of a tile (renderer.h's TileBands): laid out when the band
// begins, filled by the storing pass's fragment shader, and resolved — sorted, composited onto
// the presented images' backgrounds and stored into them — by the same worker when the band
// ends, while the lists are in its cache. A band of 128×4 pixels with dense's 71 layers holds
// 0.9 MB of lists (24 B a fragment), where a frame's lists in memory would take every record's
// line from memory and back (1.7 GB at 1080p).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "methods/depth_order.h"
#include "oitref/core/image.h"
#include "oitref/core/renderer.h"
#include "oitref/core/shader.h"
#include "oitref/oit/fragment_lists.h"

namespace oitref::methods {

struct AbufferBand {
  TileRect rect;
  int width = 0;
  std::vector<uint64_t> start;   // band pixel i = (y − y0)·width + (x − x0): its list begins at start[i]
  std::vector<uint32_t> filled;  // and holds filled[i] fragments
  // The fragments apart: what the order reads (eight to a line), what the composite reads, and
  // (only where the frame's lists are kept) the ids.
  std::vector<FragmentDepths> depths;
  std::vector<glm::vec4> colors;
  std::vector<std::array<uint32_t, 2>> ids;  // object, primitive
  bool withIds = false;
  static constexpr uint64_t kRecordBytes = sizeof(FragmentDepths) + sizeof(glm::vec4), kIdBytes = 2 * sizeof(uint32_t);
  uint64_t storeBytes() const { return depths.capacity() * sizeof(FragmentDepths) + colors.capacity() * sizeof(glm::vec4) + ids.capacity() * kIdBytes; }
  // Lets the store go where it holds more than `records` (what an earlier, larger frame left).
  void shrinkTo(uint64_t records);

  // The lists one after another, each as long as the counting pass counted (count: the whole
  // image's counts, `imageWidth` wide); with the ids where `ids`.
  void layOutCounted(const TileRect& r, const uint32_t* count, int imageWidth, bool keepIds);
  // Each list at a fixed stride of `bound` fragments, no pixel holding more: no counting pass.
  // The stride is an odd number of cache lines, so the lists' first lines spread over the
  // cache's sets (a stride of a whole number of pages puts them all in one set).
  void layOutBounded(const TileRect& r, uint64_t bound);
  static uint64_t boundedStride(uint64_t bound) { return ((bound + 1) / 2 | 1) * 2; }

  // The fragments of a batch of the band's pixels, each at the end of its pixel's list.
  void store(const FragmentBatch& in, const glm::vec4* colors) {
    const size_t row = size_t(in.y - rect.y0) * size_t(width) - size_t(rect.x0);
    for (int i = 0; i < in.count; ++i) {
      const size_t p = row + size_t(in.x[i]), slot = start[p] + filled[p]++;
      depths[slot] = {in.depth[i], in.viewDepth[i]};
      this->colors[slot] = colors[i];
      if (withIds) ids[slot] = {in.drawId, in.primitiveId};
    }
  }
  // Pixel i's fragments as the frame's lists hold them, into out.
  void copyList(size_t i, TransparentFragment* out) const;

  // Row y of the band: each list sorted front to back (the lists stay in submission order; the
  // order is of positions), composited back to front onto the pixel's background in both images
  // with OVER in fp32 (or double), and stored with α = 1 by the format's rule under the profile.
  void resolveRow(int y, Image& opaque, Image& analysis, const Profile& profile, bool useDouble);

  // What the band held: its fragments, its deepest list, its pixels with fragments.
  struct Tally {
    uint64_t fragments = 0, covered = 0;
    uint32_t deepest = 0;
    void add(const Tally& o);
  };
  Tally tally() const;

 private:
  size_t beginLayout(const TileRect& r);  // rect, width, and every list empty; returns the pixels
  std::vector<glm::vec4> texels_[2];    // a row's backgrounds in both presented images
  std::vector<glm::vec4> resolved_[2];  // the colours of its pixels with fragments, in order
  std::vector<int> columns_;            // and their columns
  std::vector<uint32_t> orders_[2];
  DepthOrder depthOrder_;
};

}  // namespace oitref::methods
