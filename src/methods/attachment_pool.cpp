// AttachmentPool (oitref/method.h): attachments kept between frames.
#include "oitref/method.h"

namespace oitref {

namespace {

// The first kept item with the format and size asked for, moved out of `kept`; else a new one.
template <typename T, typename Format>
T takeMatching(std::vector<T>& kept, const Format& format, int width, int height) {
  for (size_t i = 0; i < kept.size(); ++i)
    if (kept[i].format() == format && kept[i].width() == width && kept[i].height() == height) {
      T item = std::move(kept[i]);
      kept.erase(kept.begin() + std::ptrdiff_t(i));
      return item;
    }
  return T(format, width, height);
}

}  // namespace

Image AttachmentPool::takeImage(const Format& format, int width, int height) {
  return takeMatching(images_, format, width, height);
}

DepthBuffer AttachmentPool::takeDepth(DepthFormat format, int width, int height) {
  return takeMatching(depths_, format, width, height);
}

void AttachmentPool::give(Image&& image) {
  if (!image.bytes().empty()) images_.push_back(std::move(image));  // not one moved from
}

void AttachmentPool::give(DepthBuffer&& depth) {
  if (depth.allocated()) depths_.push_back(std::move(depth));  // not one moved from
}

void AttachmentPool::recycle(FrameResult&& frame) {
  give(std::move(frame.final8));
  give(std::move(frame.finalFloat));
  for (auto& [name, image] : frame.dump) give(std::move(image));
  frame = FrameResult{};
}

}  // namespace oitref
