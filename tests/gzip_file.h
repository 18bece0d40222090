// A gzip file's text (the recorded GPU data in tests/data/*.csv.gz).
#pragma once

#include <zlib.h>

#include <stdexcept>
#include <string>

namespace oitref::test {

inline std::string gunzip(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot read " + path);
  std::string text;
  char buf[1 << 16];
  int n;
  while ((n = gzread(f, buf, sizeof buf)) > 0) text.append(buf, size_t(n));
  gzclose(f);
  return text;
}

}  // namespace oitref::test
