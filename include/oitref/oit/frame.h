// One call from a scene to a rendered frame, as `oitref render` makes it: the scene's geometry,
// a renderer with its workers, the memory check, then the method with its options. And the
// frame's hash, the one that `oitref render` prints and reference/manifest.txt keeps.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "oitref/core/memory_limit.h"
#include "oitref/oit/method.h"
#include "oitref/core/profile.h"
#include "oitref/core/renderer.h"
#include "oitref/oit/scene.h"
#include "oitref/oit/scene_geometry.h"

namespace oitref {

// What to render. The defaults are those of `oitref render`.
struct FrameRequest {
  std::string method = "abuffer";
  std::map<std::string, std::string> options;  // the method's options (`oitref methods` lists them)
  int width = 0, height = 0;                   // 0: the scene's own size
  Profile profile = exactProfile();
  int threads = 0;                              // 0: every hardware thread
  uint64_t memoryLimit = defaultMemoryLimit();  // frames that need more are refused
};

// A scene ready for frames of any method, drawn by a renderer the caller keeps (its workers shared
// by every method and scene a tool renders): the scene at its frame size, its geometry built once,
// the profile and the memory limit. Study, suite, stress, training and glcheck render through it;
// FrameRenderer is one method's repeated frames over it. The renderer must outlive it.
class SceneFrames {
 public:
  SceneFrames(Scene scene, Renderer& renderer, Profile profile = exactProfile(), uint64_t memoryLimit = UINT64_MAX);
  // Throws std::runtime_error when the method's frame needs more than the memory limit
  // (checkMemory), before anything is allocated; with no limit there is nothing to check.
  void checkMemoryOf(const Method& method) const;
  // The method's frame, its memory checked first; `pool`: the attachments kept between frames.
  FrameResult render(Method& method, AttachmentPool* pool = nullptr) const;
  // What the method's render() gets.
  FrameContext context(AttachmentPool* pool = nullptr) const;
  const Scene& scene() const { return scene_; }
  const SceneGeometry& geometry() const { return geometry_; }
  const Profile& profile() const { return profile_; }

 private:
  Scene scene_;
  SceneGeometry geometry_;
  Renderer& renderer_;
  Profile profile_;
  uint64_t memoryLimit_;
};

// Renders frames of one scene with one method, keeping what a frame does not change between
// frames — the geometry, the renderer's workers and the attachments — as an application keeps
// its buffers. The constructor throws std::invalid_argument for an unknown method, option or
// size, and std::runtime_error for a frame that needs more memory than the limit, before
// anything is allocated.
class FrameRenderer {
 public:
  FrameRenderer(Scene scene, FrameRequest request);
  ~FrameRenderer();
  // A new frame; the previous frame's storage is reused for it, so a reference to the previous
  // result is no longer valid.
  const FrameResult& render();
  // The last frame rendered (empty before the first).
  const FrameResult& result() const { return result_; }
  // The last frame, moved out: its storage is no longer reused by the next.
  FrameResult release();
  const Method& method() const { return *method_; }
  const Scene& scene() const { return frames_.scene(); }
  Renderer& renderer() { return renderer_; }
  const FrameRequest& request() const { return request_; }

 private:
  FrameRequest request_;
  std::unique_ptr<Method> method_;
  Renderer renderer_;
  SceneFrames frames_;
  std::unique_ptr<AttachmentPool> pool_;
  FrameResult result_;
};

// One frame (FrameRenderer's first).
FrameResult renderFrame(const Scene& scene, const FrameRequest& request = {});

// SHA-256 of the frame's final RGBA8 bits, then of its RGBA32F bits, in lower-case hex.
std::string frameHash(const FrameResult& frame);

}  // namespace oitref
