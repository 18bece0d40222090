// Meshes through Assimp: every mesh of the file, node transforms applied, triangulated; vertex
// colours from the first colour set (white without one). Points and lines are dropped.
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>

#include "oitref/scene.h"

namespace oitref {

TriangleMesh loadMesh(const std::string& path) {
  if (!std::filesystem::exists(path)) throw SceneError("mesh file '" + path + "' does not exist");
  if (!std::filesystem::is_regular_file(path)) throw SceneError("mesh file '" + path + "' is not a regular file");
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw SceneError("cannot load mesh '" + path + "': " + importer.GetErrorString());
  TriangleMesh out;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const uint32_t base = uint32_t(out.positions.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw SceneError("mesh '" + path + "': vertex " + std::to_string(v) + " of mesh " + std::to_string(m) +
                         " has a non-finite coordinate");
      out.positions.emplace_back(p.x, p.y, p.z);
      if (mesh->HasVertexColors(0)) {
        const aiColor4D& c = mesh->mColors[0][v];
        out.colors.emplace_back(c.r, c.g, c.b, c.a);
      } else {
        out.colors.emplace_back(1.0f);
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
  return out;
}

}  // namespace oitref
