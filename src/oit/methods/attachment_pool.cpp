// AttachmentPool (oitref/oit/method.h): attachments kept between frames.
#include "oitref/oit/method.h"

#include <algorithm>

#include "util/huge_pages.h"

namespace oitref {
namespace {

// The first kept item of the kind asked for, moved out of `kept`, else a new one; either way the
// kind is recorded as lent.
template <typename T, typename Kind>
T takeKind(std::vector<T>& kept, std::vector<Kind>& lent, const Kind& kind) {
  lent.push_back(kind);
  for (size_t i = 0; i < kept.size(); ++i)
    if (Kind{kept[i].format(), kept[i].width(), kept[i].height()} == kind) {
      T item = std::move(kept[i]);
      kept.erase(kept.begin() + std::ptrdiff_t(i));
      return item;
    }
  return T(kind.format, kind.width, kind.height);
}

// Keeps `item` when an item of its kind is out on loan (it stands in for that one); drops it
// otherwise, so that what the pool holds never grows past what frames take from it.
template <typename T, typename Kind>
void giveKind(std::vector<T>& kept, std::vector<Kind>& lent, T&& item) {
  const auto loan = std::find(lent.begin(), lent.end(), Kind{item.format(), item.width(), item.height()});
  if (loan == lent.end()) return;
  lent.erase(loan);
  kept.push_back(std::move(item));
}

}  // namespace

Image AttachmentPool::takeImage(const Format& format, int width, int height) {
  return takeKind(images_, lentImages_, ImageKind{format, width, height});
}

DepthBuffer AttachmentPool::takeDepth(DepthFormat format, int width, int height) {
  return takeKind(depths_, lentDepths_, DepthKind{format, width, height});
}

void AttachmentPool::give(Image&& image) {
  if (!image.bytes().empty()) giveKind(images_, lentImages_, std::move(image));  // not one moved from
}

void AttachmentPool::give(DepthBuffer&& depth) {
  if (depth.allocated()) giveKind(depths_, lentDepths_, std::move(depth));  // not one moved from
}

std::vector<TransparentFragment> AttachmentPool::takeFragments(size_t n) {
  return takeBuffer(fragments_, n, true);
}

std::vector<uint64_t> AttachmentPool::takeListStarts(size_t n) {
  // Not on huge pages: read in order, they gain nothing there, and on them (in the heap, where
  // malloc puts 16 MiB) dense 1080p's A-buffer frames took 747 → 845–882 ms on one thread.
  return takeBuffer(listStarts_, n, false);
}

template <typename T>
std::vector<T> AttachmentPool::takeBuffer(Kept<T>& kept, size_t n, bool hugePages) {
  ++kept.lent;
  std::vector<T> v = std::move(kept.buffer);
  kept.buffer = {};
  if (n > v.capacity()) v = {};  // a new allocation (reserveOnHugePages), not a copy of the old one's elements
  if (hugePages) util::reserveOnHugePages(v, n);
  v.resize(n);  // shrinking touches nothing; growing value-initialises only the new part
  return v;
}

template <typename T>
void AttachmentPool::giveBuffer(Kept<T>& kept, std::vector<T>&& v) {
  if (kept.lent == 0 || v.capacity() == 0) return;  // as give(): only what stands in for a loan
  --kept.lent;
  if (v.capacity() > kept.buffer.capacity()) kept.buffer = std::move(v);
}

void AttachmentPool::recycle(FrameResult&& frame) {
  give(std::move(frame.final8));
  give(std::move(frame.finalFloat));
  for (auto& [name, image] : frame.dump) give(std::move(image));
  giveBuffer(fragments_, std::move(frame.fragmentLists.fragments));
  giveBuffer(listStarts_, std::move(frame.fragmentLists.start));
  frame = FrameResult{};
}

}  // namespace oitref
