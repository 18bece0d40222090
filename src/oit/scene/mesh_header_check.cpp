// A header that declares 400 M vertices in a 277-byte file made Assimp allocate 4.7 GB (PLY) or
// 9.4 GB (OFF) before it failed, whatever --memory-limit said. The counts are read here first and
// held against the file's size and the memory limit. The bounds are lower bounds, so a valid
// file is never refused by them: the fewest bytes a value can take in the file (its binary size,
// or one character and a separator in ASCII), and the arrays oitref itself keeps per vertex
// (position and colour, 28 bytes) and per face (one triangle's indices, 12 bytes).
#include "scene/mesh_header_check.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "oitref/core/memory_limit.h"
#include "oitref/oit/scene.h"

namespace oitref::detail {
namespace {

constexpr uint64_t kBytesPerVertex = 12 + 16;  // TriangleMesh: position, colour
constexpr uint64_t kBytesPerFace = 12;         // at least one triangle's indices

uint64_t saturatingMul(uint64_t a, uint64_t b) { return b != 0 && a > UINT64_MAX / b ? UINT64_MAX : a * b; }
uint64_t saturatingAdd(uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

void checkMemory(const std::string& path, uint64_t vertices, uint64_t faces, uint64_t limit) {
  const uint64_t need = saturatingAdd(saturatingMul(vertices, kBytesPerVertex), saturatingMul(faces, kBytesPerFace));
  if (need > limit)
    throw SceneError("mesh '" + path + "': its header declares " + std::to_string(vertices) + " vertices and " +
                     std::to_string(faces) + " faces, at least " + formatBytes(need) +
                     " once loaded (28 bytes a vertex, 12 a face), above the memory limit of " + formatBytes(limit) +
                     " (--memory-limit)");
}

void checkBody(const std::string& path, const std::string& what, uint64_t need, uint64_t available) {
  if (need > available)
    throw SceneError("mesh '" + path + "': its header declares " + what + ", at least " + std::to_string(need) +
                     " bytes of data, but the file holds " + std::to_string(available) + " bytes after its header");
}

// The bytes of one value of a PLY scalar type in a binary body (0: not a type name).
uint64_t plyTypeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32") return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

void checkPly(const std::string& path, std::ifstream& in, uint64_t fileSize, uint64_t memoryLimit) {
  struct Element {
    std::string name;
    uint64_t count = 0, binaryBytes = 0, values = 0;  // per item: bytes at the least, scalars and list counts
  };
  std::vector<Element> elements;
  bool binary = false, ended = false;
  std::string line;
  while (in.tellg() < std::streamoff(1) << 20 && std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (line == "end_header") {  // exactly, as before: Assimp loops on a header it does not end
      ended = true;
      break;
    }
    if (keyword == "format") {
      std::string encoding;
      words >> encoding;
      binary = encoding != "ascii";
    } else if (keyword == "element") {
      Element e;
      int64_t count = -1;
      words >> e.name >> count;
      if (words.fail() || count < 0) return;  // Assimp's own error says what is wrong with the line
      e.count = uint64_t(count);
      elements.push_back(e);
    } else if (keyword == "property" && !elements.empty()) {
      std::string type;
      words >> type;
      if (type == "list") words >> type;  // the list's count type: a list holds at least its count
      const uint64_t bytes = plyTypeBytes(type);
      if (bytes == 0) return;
      elements.back().binaryBytes += bytes, elements.back().values += 1;
    }
  }
  if (!ended) throw SceneError("mesh '" + path + "': PLY header has no end_header line (within its first MiB)");
  const std::streamoff header = in.tellg();
  const uint64_t available = header < 0 ? 0 : fileSize - uint64_t(header);
  uint64_t need = 0, vertices = 0, faces = 0;
  std::string what;
  for (const Element& e : elements) {
    // ASCII: each value at least one character and one separator.
    need = saturatingAdd(need, saturatingMul(e.count, binary ? e.binaryBytes : 2 * e.values));
    if (e.count > 0) what += (what.empty() ? "" : ", ") + std::to_string(e.count) + " × element '" + e.name + "'";
    if (e.name == "vertex") vertices = e.count;
    if (e.name == "face") faces = e.count;
  }
  checkBody(path, what, need, available);
  checkMemory(path, vertices, faces, memoryLimit);
}

// OFF: a keyword such as OFF, COFF, NOFF or STCNOFF (not nOFF, whose dimension comes first), then
// the vertex, face and edge counts; '#' starts a comment.
void checkOff(const std::string& path, std::ifstream& in, uint64_t fileSize, uint64_t memoryLimit) {
  std::string text, line;
  while (text.size() < 4096 && std::getline(in, line)) {
    const auto hash = line.find('#');
    text += line.substr(0, hash) + "\n";
    std::istringstream words(text);
    std::string keyword;
    int64_t v = -1, f = -1;
    words >> keyword >> v >> f;
    if (words.fail()) continue;
    if (v < 0 || f < 0) return;  // Assimp's own error
    const uint64_t vertices = uint64_t(v), faces = uint64_t(f);
    const uint64_t header = uint64_t(std::max<std::streamoff>(in.tellg(), 0));
    // Each vertex at least three one-character coordinates and separators, each face a count.
    checkBody(path, std::to_string(vertices) + " vertices and " + std::to_string(faces) + " faces",
              saturatingAdd(saturatingMul(vertices, 6), saturatingMul(faces, 2)), fileSize - std::min(fileSize, header));
    checkMemory(path, vertices, faces, memoryLimit);
    return;
  }
}

bool isOffKeyword(const std::string& word) {
  const std::string w = lower(word);
  if (w.size() < 3 || w.compare(w.size() - 3, 3, "off") != 0) return false;
  const std::string prefix = w.substr(0, w.size() - 3);
  return prefix.find_first_not_of("stcn4") == std::string::npos && word.rfind("nOFF", 0) != 0;
}

}  // namespace

void checkMeshHeader(const std::string& path, uint64_t memoryLimit) {
  std::error_code ec;
  const uint64_t fileSize = std::filesystem::file_size(path, ec);
  if (ec) return;  // the importer reports what it cannot read
  std::ifstream in(path, std::ios::binary);
  std::string first;
  if (!std::getline(in, first)) return;
  if (!first.empty() && first.back() == '\r') first.pop_back();
  if (first == "ply") return checkPly(path, in, fileSize, memoryLimit);
  std::istringstream words(first);
  std::string keyword;
  words >> keyword;
  if (lower(std::filesystem::path(path).extension().string()) == ".off" && isOffKeyword(keyword)) {
    in.clear();
    in.seekg(0);
    checkOff(path, in, fileSize, memoryLimit);
  }
}

}  // namespace oitref::detail
