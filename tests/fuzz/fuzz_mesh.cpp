// Bytes → a mesh file → loadMesh. The first byte picks the extension Assimp sees (OBJ, PLY, STL,
// glTF, OFF), the rest is the file. Bad files must end in a SceneError.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "oitref/oit/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* extensions[] = {".obj", ".ply", ".stl", ".gltf", ".off"};
  const std::string path = "/tmp/oitref-fuzz-mesh-" + std::to_string(::getpid()) + extensions[data[0] % 5];
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 1, 1, size - 1, f);
  std::fclose(f);
  try {
    (void)oitref::loadMesh(path, 5.0);  // a hang is reported as an error after 5 s
  } catch (const oitref::SceneError&) {
  }
  std::remove(path.c_str());
  return 0;
}
