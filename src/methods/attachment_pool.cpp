// AttachmentPool (oitref/method.h): attachments kept between frames.
#include "oitref/method.h"

namespace oitref {

Image AttachmentPool::takeImage(const Format& format, int width, int height) {
  for (size_t i = 0; i < images_.size(); ++i)
    if (images_[i].format() == format && images_[i].width() == width && images_[i].height() == height) {
      Image image = std::move(images_[i]);
      images_.erase(images_.begin() + std::ptrdiff_t(i));
      return image;
    }
  return Image(format, width, height);
}

DepthBuffer AttachmentPool::takeDepth(DepthFormat format, int width, int height) {
  for (size_t i = 0; i < depths_.size(); ++i)
    if (depths_[i].format() == format && depths_[i].width() == width && depths_[i].height() == height) {
      DepthBuffer depth = std::move(depths_[i]);
      depths_.erase(depths_.begin() + std::ptrdiff_t(i));
      return depth;
    }
  return DepthBuffer(format, width, height);
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
