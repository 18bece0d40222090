// Files the tests write: a folder of their own under the system's temporary directory.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace oitref::test {

// <tmp>/<name>, created if missing.
inline std::filesystem::path tempFolder(const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() / name;
  std::filesystem::create_directories(d);
  return d;
}

// Writes `bytes` to <folder>/<file> and returns the path.
inline std::string writeFile(const std::filesystem::path& folder, const std::string& file, const std::string& bytes) {
  const std::filesystem::path p = folder / file;
  std::ofstream(p, std::ios::binary) << bytes;
  return p.string();
}

}  // namespace oitref::test
