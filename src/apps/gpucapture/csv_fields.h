// The one CSV field splitter of the blend-case files: comma-separated, a trailing comma makes an
// empty last field, blanks and carriage returns around each field dropped. Standard library only,
// so oitref-gpu-capture shares it with oitref's own readers.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace oitref {

inline std::vector<std::string> splitCsvFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  for (std::string& f : fields) {
    const size_t b = f.find_first_not_of(" \t\r"), e = f.find_last_not_of(" \t\r");
    f = b == std::string::npos ? std::string() : f.substr(b, e - b + 1);
  }
  return fields;
}

}  // namespace oitref
