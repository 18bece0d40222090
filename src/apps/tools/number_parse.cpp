#include "tools/number_parse.h"

#include "oitref/core/image.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace oitref::tools {

std::optional<float> parseFloatExact(const std::string& text) {
  size_t b = text.find_first_not_of(" \t\r");
  size_t e = text.find_last_not_of(" \t\r");
  if (b == std::string::npos) return std::nullopt;
  const std::string t = text.substr(b, e - b + 1);
  const char* begin = t.c_str();
  char* end = nullptr;
  errno = 0;
  const float v = std::strtof(begin, &end);  // glibc: correctly rounded, hex floats, nan/inf
  if (end != begin + t.size()) return std::nullopt;
  return v;  // ERANGE still yields the correctly rounded result (±inf, denormal or 0)
}

glm::vec4 parseVec4(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  std::string part;
  glm::vec4 v(0.0f);
  int i = 0;
  while (std::getline(in, part, ',')) {
    if (i == 4) throw std::invalid_argument(what + ": more than 4 components in '" + text + "'");
    const auto f = parseFloatExact(part);
    if (!f) throw std::invalid_argument(what + ": component " + std::to_string(i + 1) + " '" + part +
                                        "' is not a number (decimal, hex float, nan, inf)");
    v[i++] = *f;
  }
  if (i != 4) throw std::invalid_argument(what + ": expected 4 components r,g,b,a, got " + std::to_string(i));
  return v;
}

void parseSize(const std::string& text, const std::string& what, int& width, int& height) {
  int w = 0, h = 0;
  char x = 0;
  std::string rest;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || x != 'x' || (in >> rest) || w < 1 || h < 1 || w > Image::kMaxDimension ||
      h > Image::kMaxDimension)
    throw std::invalid_argument(what + " '" + text + "': expected WxH with 1 ≤ W, H ≤ " +
                                std::to_string(Image::kMaxDimension));
  width = w, height = h;
}

uint64_t parseByteSize(const std::string& text, const std::string& what) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  std::string unit(end);
  if (unit.size() >= 2 && unit.substr(unit.size() - 2) == "iB") unit.resize(unit.size() - 2);
  else if (unit == "B") unit.clear();
  const std::string units = "KMGT";
  const size_t power = unit.empty() ? 0 : (unit.size() == 1 ? units.find(unit[0]) + 1 : 0);
  const double bytes = v * std::ldexp(1.0, 10 * int(power));
  if (end == text.c_str() || errno || !(v > 0) || (!unit.empty() && (unit.size() != 1 || power == 0)) ||
      !(bytes < 0x1p63))
    throw std::invalid_argument(what + " '" + text + "': expected a positive size such as 8G, 512M or 1048576");
  return uint64_t(bytes);
}

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", unsigned(c));
      o += esc;
      continue;
    }
    o += c;
  }
  return o + "\"";
}

std::string jsonNumber(double v) {
  if (std::isnan(v)) return "\"nan\"";
  if (std::isinf(v)) return v > 0 ? "\"inf\"" : "\"-inf\"";
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

std::string hexFloat(float value) {
  if (std::isnan(value)) return std::signbit(value) ? "-nan" : "nan";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%a", double(value));
  return buf;
}

}  // namespace oitref::tools
