// Scenes: the JSON scene files of Rožek's OIT thesis (appendix B.2), extended with a camera and
// a resolution.
//
//   { "back": [r,g,b],                          background colour, linear
//     "resolution": [w,h],
//     "camera": {"position":[x,y,z], "target":[x,y,z], "up":[0,1,0], "fov_y":60, "near":0.1, "far":100},
//     "objects": [
//       {"type":"mesh", "file_path":"meshes/bunny.ply", "color_override":[r,g,b,a],
//        "position":[x,y,z], "rotation":[x,y,z], "scale":s, "transparent":true},
//       {"type":"particle", "count":32, "seed":1, "color_override":[r,g,b,a],
//        "position":[x,y,z], "rotation":[x,y,z], "scale":s, "size":t} ] }
//
// Textures (either object type): "texture":"leaf.png" (else a mesh's material's diffuse texture,
// beside the model), "texture_format":"rgba8"|"srgb8_alpha8" (default rgba8: the file's bytes
// are the values), "sampler":{"min_filter":"linear_mipmap_linear", "mag_filter":"linear",
// "wrap_s":"repeat", "wrap_t":"repeat", "lod_bias":0} (GL's defaults where absent), and
// "alpha_test":0.5 (discard where the textured alpha is below it).
//
// A particle cloud's centres lie in the unit ball placed by the model matrix (so "rotation"
// turns the cloud about its position); each particle is a square of side "size" facing the camera.
//
// Conventions: paths relative to the scene file; rotation in degrees; model matrix
// T·Rz·Ry·Rx·S; camera glm::lookAt + glm::perspective (right-handed, clip z in [−w, w]); colours
// straight (not premultiplied) and linear. An object is transparent when its alpha is below 1
// anywhere, unless "transparent" says otherwise.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "oitref/core/texture.h"

namespace oitref {

// The largest coordinate the ray cast can trace with: Embree's FLT_LARGE. Its ray origins and
// vertices beyond it trip an assertion inside the library (a camera at x = −1.2e19 aborted the
// process), so Camera::projectionProblem refuses such positions and the ray cast such vertices.
inline constexpr float kRayCastLargestCoordinate = 1.844e18f;

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 60.0f;
  float nearPlane = 0.1f;
  float farPlane = 100.0f;

  glm::mat4 view() const;
  // Throws std::invalid_argument with projectionProblem's reason when there is one.
  glm::mat4 projection(float aspect) const;
  // Why the fp32 projection at this aspect cannot show anything, or "": an entry that is not finite
  // (a tiny fov_y, 2·far·near beyond fp32), or one that cannot be undone into finite rays through
  // the view's corners (a near and far so far apart that every depth is the far plane's). The one
  // check of both ground truths: the rasterizer and the ray cast refuse the same cameras.
  std::string projectionProblem(float aspect) const;
};

// A mesh as loaded, in object space: triangles, per-vertex straight RGBA (white when the file
// has none), texture coordinates (the first set; empty when the file has none) and the diffuse
// texture its materials name (resolved against the model's folder; empty for none).
struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec4> colors;
  std::vector<glm::vec2> texcoords;
  std::vector<uint32_t> indices;  // three per triangle
  std::string texturePath;
};

enum class ObjectType : uint8_t { Mesh, Particles };

struct SceneObject {
  ObjectType type = ObjectType::Mesh;
  std::optional<glm::vec4> colorOverride;
  glm::vec3 position{0.0f};
  glm::vec3 rotationDegrees{0.0f};
  float scale = 1.0f;
  std::optional<bool> transparentOverride;

  // Mesh objects.
  std::string filePath;  // resolved against the scene file's folder
  TriangleMesh mesh;

  // Particle objects: `count` camera-facing quads of edge `size` at seeded positions inside a
  // sphere of radius `scale` around `position`.
  int particleCount = 0;
  uint32_t seed = 1;
  float particleSize = 0.5f;

  // A texture multiplied into the colour (shadeSurface), from "texture" or the mesh's material:
  // sampled at the mesh's texture coordinates, or a particle's quad coordinates. textureFile
  // names it in reports; "alpha_test" discards fragments whose alpha is below the threshold.
  std::shared_ptr<const Texture2D> texture;
  std::string textureFile;
  TextureFormat textureFormat = TextureFormat::Rgba8;
  SamplerState sampler;
  std::optional<float> alphaTest;

  glm::mat4 modelMatrix() const;  // T·Rz·Ry·Rx·S
  bool isTransparent() const;     // the override, else alpha < 1 anywhere (vertex, override or texel)
};

struct Scene {
  glm::vec3 background{0.0f};
  int width = 640, height = 360;
  Camera camera;
  std::vector<SceneObject> objects;
  std::string sourcePath;
};

// Loads a scene file and its meshes. Throws SceneError naming the file, the JSON field
// (e.g. "objects[2].color_override[3]") and what was expected.
// `memoryLimit` (--memory-limit) bounds what a mesh file's header may declare (loadMesh).
Scene loadScene(const std::string& path, uint64_t memoryLimit = UINT64_MAX);
// The same from the scene's JSON text: `path` names it in errors and anchors relative mesh and
// texture paths (it need not exist).
Scene loadSceneText(const std::string& jsonText, const std::string& path, uint64_t memoryLimit = UINT64_MAX);
// Parses scene JSON text alone — no mesh or texture is read (loadSceneText reads them); `path`
// names it in errors and anchors relative mesh paths.
Scene parseScene(const std::string& jsonText, const std::string& path);
// Loads a mesh through Assimp (OBJ, PLY ascii/binary with vertex colours, FBX, glTF, ...), in a
// child process that may take at most `timeoutSeconds`: a malformed file is a SceneError, even
// when it makes Assimp abort or hang. Before Assimp runs, counts that the file's header declares
// (PLY, OFF) are held against the file's size and `memoryLimit`: a 277-byte file cannot make it
// allocate gigabytes.
TriangleMesh loadMesh(const std::string& path, double timeoutSeconds = 120.0, uint64_t memoryLimit = UINT64_MAX);

struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace oitref
