// Scene JSON text → parseScene. Bad input must end in a SceneError naming the file and field;
// anything else (a crash, a sanitizer report, another exception) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oitref/oit/scene.h"
#include "oitref/oit/scene_geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    oitref::Scene scene = oitref::parseScene(text, "fuzz.json");
    // Particles are built from the parsed fields; meshes are not loaded here (fuzz_mesh does).
    for (oitref::SceneObject& o : scene.objects)
      if (o.type == oitref::ObjectType::Particles) o.particleCount = std::min(o.particleCount, 64);
    std::erase_if(scene.objects, [](const oitref::SceneObject& o) { return o.type == oitref::ObjectType::Mesh; });
    (void)oitref::buildSceneGeometry(scene);
  } catch (const oitref::SceneError&) {
  }
  return 0;
}
