// Exact number parsing and printing for the command line and CSV.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <glm/vec4.hpp>

namespace oitref::tools {

// Decimal ("0.1", "1e-3"), C99 hex float ("0x1.8p-3"), "nan", "inf", "-inf" -> fp32, correctly
// rounded (strtof). nullopt when the whole text is not one number.
std::optional<float> parseFloatExact(const std::string& text);
// "r,g,b,a" -> vec4. Throws std::invalid_argument naming `what` and the bad component.
glm::vec4 parseVec4(const std::string& text, const std::string& what);
// "WxH" -> width, height with 1 ≤ W, H ≤ Image::kMaxDimension. Throws std::invalid_argument
// naming `what` (e.g. "--size").
void parseSize(const std::string& text, const std::string& what, int& width, int& height);
// A byte count: "4096", "512M", "1.5GiB", "8G" (K, M, G, T with or without "iB": powers of 1024).
// Throws std::invalid_argument naming `what`.
uint64_t parseByteSize(const std::string& text, const std::string& what);
// JSON text: a quoted, escaped string; a number with 9 significant digits, or "nan"/"inf"/"-inf"
// as strings (JSON has no such numbers).
std::string jsonString(const std::string& s);
std::string jsonNumber(double v);
// Hex float that round-trips ("0x1.8p-3", "0x0p+0", "nan", "-inf").
std::string hexFloat(float value);

}  // namespace oitref::tools
