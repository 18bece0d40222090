// What a mesh file's header declares, checked before the importer runs (scene/mesh_loader.cpp).
#pragma once

#include <cstdint>
#include <string>

namespace oitref::detail {

// For files whose header declares their sizes (PLY's elements, OFF's vertex and face counts):
// throws SceneError naming the file when the header declares more data than the file can hold
// (at the fewest bytes per value its encoding allows), or a mesh whose arrays alone would need
// more than `memoryLimit` bytes once loaded. Also refuses a PLY header that never ends (Assimp
// 5.2.5 loops forever on one). Other files pass unread.
void checkMeshHeader(const std::string& path, uint64_t memoryLimit);

}  // namespace oitref::detail
