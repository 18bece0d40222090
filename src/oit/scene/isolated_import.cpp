#include "scene/isolated_import.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <vector>

namespace oitref::detail {
namespace {

// The child's message: a status byte (0 mesh, 1 error), then the mesh as counts and raw arrays
// (positions, colours, texture coordinates, indices, the texture path's bytes), or the error text.
void append(std::vector<char>& out, const void* data, size_t bytes) {
  const char* p = static_cast<const char*>(data);
  out.insert(out.end(), p, p + bytes);
}

std::vector<char> encode(const TriangleMesh& m) {
  std::vector<char> out(1, 0);
  const uint64_t vertices = m.positions.size(), indices = m.indices.size(), texcoords = m.texcoords.size(),
                 pathBytes = m.texturePath.size();
  append(out, &vertices, 8);
  append(out, &indices, 8);
  append(out, &texcoords, 8);
  append(out, &pathBytes, 8);
  append(out, m.positions.data(), vertices * sizeof(glm::vec3));
  append(out, m.colors.data(), vertices * sizeof(glm::vec4));
  append(out, m.texcoords.data(), texcoords * sizeof(glm::vec2));
  append(out, m.indices.data(), indices * sizeof(uint32_t));
  append(out, m.texturePath.data(), pathBytes);
  return out;
}

bool decode(const std::vector<char>& in, TriangleMesh& m) {
  uint64_t vertices = 0, indices = 0, texcoords = 0, pathBytes = 0;
  constexpr size_t kHeader = 33;
  if (in.size() < kHeader) return false;
  std::memcpy(&vertices, in.data() + 1, 8);
  std::memcpy(&indices, in.data() + 9, 8);
  std::memcpy(&texcoords, in.data() + 17, 8);
  std::memcpy(&pathBytes, in.data() + 25, 8);
  if (vertices > in.size() || indices > in.size() || texcoords > in.size() || pathBytes > in.size()) return false;
  const uint64_t need = kHeader + vertices * (sizeof(glm::vec3) + sizeof(glm::vec4)) + texcoords * sizeof(glm::vec2) +
                        indices * 4 + pathBytes;
  if (in.size() != need) return false;
  m.positions.resize(vertices);
  m.colors.resize(vertices);
  m.texcoords.resize(texcoords);
  m.indices.resize(indices);
  const char* p = in.data() + kHeader;
  std::memcpy(m.positions.data(), p, vertices * sizeof(glm::vec3));
  p += vertices * sizeof(glm::vec3);
  std::memcpy(m.colors.data(), p, vertices * sizeof(glm::vec4));
  p += vertices * sizeof(glm::vec4);
  if (texcoords) std::memcpy(m.texcoords.data(), p, texcoords * sizeof(glm::vec2));  // data() may be null for none
  p += texcoords * sizeof(glm::vec2);
  std::memcpy(m.indices.data(), p, indices * 4);
  p += indices * 4;
  m.texturePath.assign(p, pathBytes);
  return true;
}

[[noreturn]] void runChild(int fd, const std::string& path, MeshImporter import) {
  std::vector<char> message;
  try {
    message = encode(import(path));
  } catch (const std::exception& e) {
    message.assign(1, 1);
    append(message, e.what(), std::strlen(e.what()));
  }
  for (size_t done = 0; done < message.size();) {
    const ssize_t n = ::write(fd, message.data() + done, message.size() - done);
    if (n <= 0) _exit(3);
    done += size_t(n);
  }
  _exit(0);  // no destructors, no atexit handlers: the child only reports
}

}  // namespace

TriangleMesh importIsolated(const std::string& path, MeshImporter import, double timeoutSeconds) {
  int fds[2];
  if (::pipe(fds) != 0) throw SceneError("mesh '" + path + "': cannot create a pipe for the importer");
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw SceneError("mesh '" + path + "': cannot start the importer process");
  }
  if (child == 0) {
    ::close(fds[0]);
    // Assimp writes its internal assertions ("ai_assert failure in …TriangulateProcess.cpp")
    // to stderr before it aborts: the user gets oitref's error naming the file instead.
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, STDOUT_FILENO), ::dup2(null, STDERR_FILENO);
    runChild(fds[1], path, import);
  }
  ::close(fds[1]);
  std::vector<char> message;
  bool timedOut = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
  char buffer[1 << 16];
  for (;;) {
    const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      timedOut = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, int(left * 1000) + 1);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;  // the deadline check ends the loop
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child closed its end
    message.insert(message.end(), buffer, buffer + n);
  }
  ::close(fds[0]);
  if (timedOut) ::kill(child, SIGKILL);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (timedOut)
    throw SceneError("mesh '" + path + "': the importer (Assimp) did not finish within " +
                     std::to_string(int(timeoutSeconds)) + " s; the file is probably malformed");
  if (WIFSIGNALED(status))
    throw SceneError("mesh '" + path + "': the importer (Assimp) crashed on this file (signal " +
                     std::to_string(WTERMSIG(status)) + " " + strsignal(WTERMSIG(status)) + "); the file is malformed");
  if (!message.empty() && message[0] == 1) throw SceneError(std::string(message.begin() + 1, message.end()));
  TriangleMesh mesh;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || message.empty() || !decode(message, mesh))
    throw SceneError("mesh '" + path + "': the importer process failed (exit status " +
                     std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  return mesh;
}

}  // namespace oitref::detail
