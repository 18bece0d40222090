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

SceneFrames::SceneFrames(Scene scene, Renderer& renderer, Profile profile, uint64_t memoryLimit)
    : scene_(std::move(scene)), geometry_(buildSceneGeometry(scene_)), renderer_(renderer), profile_(profile),
      memoryLimit_(memoryLimit) {}

void SceneFrames::checkMemoryOf(const Method& method) const {
  if (memoryLimit_ != UINT64_MAX) checkMemory(method, scene_.width, scene_.height, geometry_, memoryLimit_);
}

FrameResult SceneFrames::render(Method& method, AttachmentPool* pool) const {
  checkMemoryOf(method);
  return method.render(context(pool));
}

FrameContext SceneFrames::context(AttachmentPool* pool) const {
  return FrameContext{scene_, geometry_, scene_.width, scene_.height, profile_, renderer_, memoryLimit_, pool};
}

FrameRenderer::FrameRenderer(Scene scene, FrameRequest request)
    : request_(std::move(request)),
      method_(makeMethod(request_.method, request_.options)),  // a bad method or option: before the scene's geometry
      renderer_(RendererOptions{.threads = request_.threads}),
      frames_(sized(std::move(scene), request_), renderer_, request_.profile, request_.memoryLimit),
      pool_(std::make_unique<AttachmentPool>()) {
  frames_.checkMemoryOf(*method_);
}

FrameRenderer::~FrameRenderer() = default;

const FrameResult& FrameRenderer::render() {
  pool_->recycle(std::move(result_));
  result_ = method_->render(frames_.context(pool_.get()));
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
