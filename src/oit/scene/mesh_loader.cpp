// Meshes through Assimp: every mesh of the file, node transforms applied, triangulated; vertex
// colours from the first colour set (white without one), texture coordinates from the first set,
// and the diffuse texture of the meshes' materials. Points and lines are dropped. Assimp runs in
// a child process (scene/isolated_import.h): it aborts and hangs on some malformed files.
//
// One texture per object, as the thesis's render objects have ("each render object can have only
// one texture"): a file whose meshes name different diffuse textures, or some a texture and some
// none, is refused with the names, as is a textured mesh without texture coordinates.
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "oitref/oit/scene.h"
#include "scene/colour_rule.h"
#include "scene/isolated_import.h"
#include "scene/mesh_header_check.h"

namespace oitref {
namespace {

// The diffuse texture a mesh's material names, resolved against the model's folder ("" for none).
std::string diffuseTexture(const aiScene* scene, const aiMesh* mesh, const std::string& path) {
  if (mesh->mMaterialIndex >= scene->mNumMaterials) return "";
  aiString name;
  if (scene->mMaterials[mesh->mMaterialIndex]->GetTexture(aiTextureType_DIFFUSE, 0, &name) != aiReturn_SUCCESS)
    return "";
  std::string file = name.C_Str();
  if (file.empty()) return "";
  if (file[0] == '*')
    throw SceneError("mesh '" + path + "': its material embeds the diffuse texture '" + file +
                     "'; oitref reads textures from files beside the model: save it there and name it in the material");
  std::replace(file.begin(), file.end(), '\\', '/');  // paths written on Windows
  return (std::filesystem::path(path).parent_path() / file).lexically_normal().string();
}

TriangleMesh importWithAssimp(const std::string& path) {
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw SceneError("cannot load mesh '" + path + "': " + importer.GetErrorString());
  TriangleMesh out;
  int firstMesh = -1;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const std::string texture = diffuseTexture(scene, mesh, path);
    if (firstMesh < 0) {
      firstMesh = int(m);
      out.texturePath = texture;
    } else if (texture != out.texturePath) {
      auto named = [](const std::string& t) { return t.empty() ? std::string("no diffuse texture") : "the diffuse texture '" + t + "'"; };
      throw SceneError("mesh '" + path + "': mesh " + std::to_string(firstMesh) + " has " + named(out.texturePath) +
                       " and mesh " + std::to_string(m) + " has " + named(texture) +
                       "; an object has one texture (as the thesis's render objects): split the model into one file per texture");
    }
    if (!texture.empty() && !mesh->HasTextureCoords(0))
      throw SceneError("mesh '" + path + "': mesh " + std::to_string(m) + " has the diffuse texture '" + texture +
                       "' but no texture coordinates");
    const uint32_t base = uint32_t(out.positions.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw SceneError("mesh '" + path + "': vertex " + std::to_string(v) + " of mesh " + std::to_string(m) +
                         " has a non-finite coordinate");
      out.positions.emplace_back(p.x, p.y, p.z);
      if (mesh->HasVertexColors(0)) {
        const aiColor4D& c = mesh->mColors[0][v];
        const glm::vec4 colour(c.r, c.g, c.b, c.a);
        int channel = 0;  // the same rule as color_override's
        if (const char* problem = detail::colourProblem(colour, channel))
          throw SceneError("mesh '" + path + "': vertex " + std::to_string(v) + " of mesh " + std::to_string(m) + ", colour channel " +
                           "rgba"[channel] + " (" + std::to_string(colour[channel]) + "): " + problem);
        out.colors.push_back(colour);
      } else {
        out.colors.emplace_back(1.0f);
      }
      if (mesh->HasTextureCoords(0)) {
        const aiVector3D& uv = mesh->mTextureCoords[0][v];
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
          throw SceneError("mesh '" + path + "': vertex " + std::to_string(v) + " of mesh " + std::to_string(m) +
                           " has a non-finite texture coordinate");
        out.texcoords.emplace_back(uv.x, uv.y);
      }
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= mesh->mNumVertices)
          throw SceneError("mesh '" + path + "': face " + std::to_string(f) + " has an index out of range");
        out.indices.push_back(base + face.mIndices[k]);
      }
    }
  }
  if (out.indices.empty()) throw SceneError("mesh '" + path + "' has no triangles");
  // Texture coordinates only where every mesh has them (a texture named by the scene needs them
  // everywhere; one named by a material was checked above).
  if (out.texcoords.size() != out.positions.size()) out.texcoords.clear();
  return out;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, double timeoutSeconds, uint64_t memoryLimit) {
  if (!std::filesystem::exists(path)) throw SceneError("mesh file '" + path + "' does not exist");
  if (!std::filesystem::is_regular_file(path)) throw SceneError("mesh file '" + path + "' is not a regular file");
  detail::checkMeshHeader(path, memoryLimit);  // declared counts against the file and the limit
  return detail::importIsolated(path, importWithAssimp, timeoutSeconds);
}

}  // namespace oitref
