// Runs a mesh importer in a child process, so that a third-party parser that aborts, crashes or
// hangs on a malformed file (Debian 12's Assimp 5.2.5 does all three; tests/fuzz/regressions)
// becomes a SceneError naming the file instead of taking oitref down. The child sends the mesh
// back through a pipe; the parent waits at most `timeoutSeconds`, then kills it.
#pragma once

#include <string>

#include "oitref/oit/scene.h"

namespace oitref::detail {

using MeshImporter = TriangleMesh (*)(const std::string& path);

// Throws SceneError with the child's SceneError message, or saying how the importer died.
TriangleMesh importIsolated(const std::string& path, MeshImporter import, double timeoutSeconds);

}  // namespace oitref::detail
