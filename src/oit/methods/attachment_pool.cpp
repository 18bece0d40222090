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
  ++lentFragments_;
  std::vector<TransparentFragment> v = std::move(fragments_);
  fragments_ = {};
  if (n > v.capacity()) v = {};  // a new allocation (reserveOnHugePages), not a copy of the old one's elements
  util::reserveOnHugePages(v, n);
  v.resize(n);  // shrinking touches nothing; growing value-initialises only the new part
  return v;
}

void AttachmentPool::recycle(FrameResult&& frame) {
  give(std::move(frame.final8));
  give(std::move(frame.finalFloat));
  for (auto& [name, image] : frame.dump) give(std::move(image));
  std::vector<TransparentFragment>& fragments = frame.fragmentLists.fragments;
  if (lentFragments_ > 0 && fragments.capacity() > 0) {  // as give(): only what stands in for a loan
    --lentFragments_;
    if (fragments.capacity() > fragments_.capacity()) fragments_ = std::move(fragments);
  }
  frame = FrameResult{};
}

}  // namespace oitref
