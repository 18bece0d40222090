// FrameRenderer, renderFrame and frameHash (oitref/oit/frame.h).
#include "oitref/oit/frame.h"

#include <stdexcept>
#include <utility>

#include "frame/sha256.h"

namespace oitref {
namespace {

Scene sized(Scene scene, const FrameRequest& r) {
  const std::string size = std::to_string(r.width) + "x" + std::to_string(r.height);
  if (r.width < 0 || r.height < 0 || (r.width == 0) != (r.height == 0))
    throw std::invalid_argument("frame size " + size + ": give both sides, or neither for the scene's own size");
  if (r.width > Image::kMaxDimension || r.height > Image::kMaxDimension)  // as a scene's resolution and --size
    throw std::invalid_argument("frame size " + size + ": each side at most " + std::to_string(Image::kMaxDimension));
  if (r.width > 0) scene.width = r.width, scene.height = r.height;
  return scene;
}

}  // namespace

FrameRenderer::FrameRenderer(Scene scene, FrameRequest request)
    : scene_(sized(std::move(scene), request)),
      request_(std::move(request)),
      method_(makeMethod(request_.method, request_.options)),
      geometry_(buildSceneGeometry(scene_)),
      renderer_(RendererOptions{.threads = request_.threads}),
      pool_(std::make_unique<AttachmentPool>()) {
  checkMemory(*method_, scene_.width, scene_.height, geometry_, request_.memoryLimit);
}

FrameRenderer::~FrameRenderer() = default;

const FrameResult& FrameRenderer::render() {
  pool_->recycle(std::move(result_));
  const FrameContext context{scene_, geometry_, scene_.width, scene_.height, request_.profile,
                             renderer_, request_.memoryLimit, pool_.get()};
  result_ = method_->render(context);
  return result_;
}

FrameResult FrameRenderer::release() { return std::exchange(result_, FrameResult{}); }

FrameResult renderFrame(const Scene& scene, const FrameRequest& request) {
  FrameRenderer frames(scene, request);
  frames.render();
  return frames.release();
}

std::string frameHash(const FrameResult& frame) {
  util::Sha256 sha;
  sha.update(frame.final8.bytes().data(), frame.final8.bytes().size());
  sha.update(frame.finalFloat.bytes().data(), frame.finalFloat.bytes().size());
  return sha.hex();
}

}  // namespace oitref
