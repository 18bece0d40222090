// oitref-gpu-capture: runs blend cases on the machine's GPU through headless EGL and records what
// the driver stored, so oitref can be checked against that GPU anywhere (`oitref blend --cases`).
//
//   oitref-gpu-capture blend CASES.csv OUT.csv
//   oitref-gpu-capture frames TRACE READS
//   oitref-gpu-capture sampling OUT.csv       (the texture unit's weights: sampling_capture.h)
//
// CASES.csv has the 19 input columns of `oitref blend --cases` (header line first); other columns
// are kept. OUT.csv repeats every line and adds gpu_dst_bits (the texel after the destination was
// written with blending off) and gpu_result_bits (after the source was blended onto it), laid out
// as oitref's dst_bits/result_bits: hex per channel, or one 32-bit word for packed formats as GL's
// UNSIGNED_INT_2_10_10_10_REV / UNSIGNED_INT_10F_11F_11F_REV read them. Existing gpu_* columns are
// replaced. The driver's vendor, renderer and version go to stderr.
//
// It needs only a C++17 compiler, the EGL and GL headers and libEGL at run time, so it builds on
// one machine and runs on another (CMake target oitref_gpu_capture, or one line:
//   g++ -std=c++17 -O2 -Isrc src/apps/gpucapture/*.cpp src/apps/glcheck/gl_context.cpp -lEGL
//       -static-libstdc++ -static-libgcc -o oitref-gpu-capture).
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "glcheck/gl_context.h"
#include "gpucapture/blend_capture.h"
#include "gpucapture/csv_fields.h"
#include "gpucapture/gl_trace.h"
#include "gpucapture/sampling_capture.h"

namespace {

using oitref::glcheck::GlBlendCase;
using oitref::glcheck::GlTargetFormat;

struct FormatInfo {
  const char* name;
  GlTargetFormat gl;
  int channels, bytesPerChannel;  // bytesPerChannel 0: one packed 32-bit word
};

const FormatInfo kFormats[] = {
    {"r8", {GL_R8, GL_RED, GL_UNSIGNED_BYTE, 1}, 1, 1},
    {"rg8", {GL_RG8, GL_RG, GL_UNSIGNED_BYTE, 2}, 2, 1},
    {"rgba8", {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, 4}, 4, 1},
    {"r16", {GL_R16, GL_RED, GL_UNSIGNED_SHORT, 2}, 1, 2},
    {"rg16", {GL_RG16, GL_RG, GL_UNSIGNED_SHORT, 4}, 2, 2},
    {"rgba16", {GL_RGBA16, GL_RGBA, GL_UNSIGNED_SHORT, 8}, 4, 2},
    {"rgb10a2", {GL_RGB10_A2, GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV, 4}, 4, 0},
    {"r16f", {GL_R16F, GL_RED, GL_HALF_FLOAT, 2}, 1, 2},
    {"rg16f", {GL_RG16F, GL_RG, GL_HALF_FLOAT, 4}, 2, 2},
    {"rgba16f", {GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT, 8}, 4, 2},
    {"r32f", {GL_R32F, GL_RED, GL_FLOAT, 4}, 1, 4},
    {"rg32f", {GL_RG32F, GL_RG, GL_FLOAT, 8}, 2, 4},
    {"rgba32f", {GL_RGBA32F, GL_RGBA, GL_FLOAT, 16}, 4, 4},
    {"r11g11b10f", {GL_R11F_G11F_B10F, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV, 4}, 3, 0},
};

const char* const kEquations[] = {"add", "subtract", "reverse_subtract", "min", "max"};
const GLenum kGlEquations[] = {GL_FUNC_ADD, GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT, GL_MIN, GL_MAX};
const char* const kFactors[] = {"zero", "one", "src_color", "one_minus_src_color", "dst_color", "one_minus_dst_color",
                                "src_alpha", "one_minus_src_alpha", "dst_alpha", "one_minus_dst_alpha",
                                "constant_color", "one_minus_constant_color", "constant_alpha",
                                "one_minus_constant_alpha", "src_alpha_saturate"};
const GLenum kGlFactors[] = {GL_ZERO, GL_ONE, GL_SRC_COLOR, GL_ONE_MINUS_SRC_COLOR, GL_DST_COLOR,
                             GL_ONE_MINUS_DST_COLOR, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_DST_ALPHA,
                             GL_ONE_MINUS_DST_ALPHA, GL_CONSTANT_COLOR, GL_ONE_MINUS_CONSTANT_COLOR,
                             GL_CONSTANT_ALPHA, GL_ONE_MINUS_CONSTANT_ALPHA, GL_SRC_ALPHA_SATURATE};
const char* const kInputColumns[19] = {"format",  "eq_rgb",  "eq_alpha", "src_rgb", "dst_rgb", "src_alpha", "dst_alpha",
                                       "const_r", "const_g", "const_b",  "const_a", "dst_r",   "dst_g",     "dst_b",
                                       "dst_a",   "src_r",   "src_g",    "src_b",   "src_a"};

template <size_t N>
size_t indexOf(const char* const (&names)[N], const std::string& s, const char* what) {
  for (size_t i = 0; i < N; ++i)
    if (s == names[i]) return i;
  throw std::invalid_argument("unknown " + std::string(what) + " '" + s + "'");
}

// The nearest fp32, as oitref parses (decimal, C99 hex float, nan, inf, -inf).
uint32_t parseBits(const std::string& s) {
  char* end = nullptr;
  errno = 0;
  const float v = std::strtof(s.c_str(), &end);
  if (s.empty() || *end != '\0') throw std::invalid_argument("'" + s + "' is not a number");
  uint32_t b;
  std::memcpy(&b, &v, 4);
  return b;
}

std::string bitsText(const FormatInfo& f, const uint8_t* texel) {
  char buf[16];
  if (f.bytesPerChannel == 0) {
    uint32_t w;
    std::memcpy(&w, texel, 4);
    std::snprintf(buf, sizeof buf, "%08x", w);
    return buf;
  }
  std::string s;
  for (int c = 0; c < f.channels; ++c) {
    uint32_t v = 0;
    std::memcpy(&v, texel + c * f.bytesPerChannel, size_t(f.bytesPerChannel));
    std::snprintf(buf, sizeof buf, "%0*x", f.bytesPerChannel * 2, v);
    s += (c ? " " : "") + std::string(buf);
  }
  return s;
}

const FormatInfo& formatNamed(const std::string& name) {
  for (const FormatInfo& f : kFormats)
    if (name == f.name) return f;
  throw std::invalid_argument("format '" + name + "' is not one GL renders to (r8 ... r11g11b10f)");
}

int runBlend(const char* inPath, const char* outPath) {
  std::ifstream in(inPath);
  if (!in) throw std::runtime_error(std::string("cannot read '") + inPath + "'");
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(std::string(inPath) + ": empty file (a header line is needed)");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::vector<std::string> header = oitref::splitCsvFields(line);
  size_t column[19];
  for (int i = 0; i < 19; ++i) {
    size_t j = 0;
    while (j < header.size() && header[j] != kInputColumns[i]) ++j;
    if (j == header.size()) throw std::runtime_error(std::string(inPath) + ": header has no column '" + kInputColumns[i] + "'");
    column[i] = j;
  }
  std::vector<size_t> kept;  // every column but earlier gpu_* results
  for (size_t j = 0; j < header.size(); ++j)
    if (header[j] != "gpu_dst_bits" && header[j] != "gpu_result_bits") kept.push_back(j);

  std::vector<GlBlendCase> cases;
  std::vector<const FormatInfo*> formats;
  std::vector<std::vector<std::string>> rows;
  int lineNo = 1, bad = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> f = oitref::splitCsvFields(line);
    try {
      if (f.size() != header.size())
        throw std::invalid_argument(std::to_string(f.size()) + " fields where the header has " + std::to_string(header.size()));
      const FormatInfo& fmt = formatNamed(f[column[0]]);
      GlBlendCase c{};
      c.format = fmt.gl;
      c.equationRgb = kGlEquations[indexOf(kEquations, f[column[1]], "equation")];
      c.equationAlpha = kGlEquations[indexOf(kEquations, f[column[2]], "equation")];
      GLenum* factors[4] = {&c.srcRgb, &c.dstRgb, &c.srcAlpha, &c.dstAlpha};
      for (int i = 0; i < 4; ++i) *factors[i] = kGlFactors[indexOf(kFactors, f[column[3 + i]], "blend factor")];
      for (int i = 0; i < 4; ++i) {
        const uint32_t k = parseBits(f[column[7 + i]]);
        std::memcpy(&c.constant[size_t(i)], &k, 4);
        c.destination[size_t(i)] = parseBits(f[column[11 + i]]);
        c.source[size_t(i)] = parseBits(f[column[15 + i]]);
      }
      cases.push_back(c);
      formats.push_back(&fmt);
      rows.push_back(f);
    } catch (const std::invalid_argument& e) {
      std::cerr << inPath << ": line " << lineNo << ": " << e.what() << "\n";
      ++bad;
    }
  }
  oitref::glcheck::GlContext context;
  std::cerr << "GL: " << context.vendor() << " | " << context.renderer() << " | " << context.version() << " ("
            << context.platform() << " platform)\n";
  const std::vector<oitref::glcheck::GlTexels> texels = oitref::glcheck::captureBlendCases(context.gl(), cases);

  std::ofstream out(outPath);
  if (!out) throw std::runtime_error(std::string("cannot write '") + outPath + "'");
  for (size_t j : kept) out << header[j] << ",";
  out << "gpu_dst_bits,gpu_result_bits\n";
  for (size_t i = 0; i < cases.size(); ++i) {
    for (size_t j : kept) out << rows[i][j] << ",";
    out << bitsText(*formats[i], texels[i].destination.data()) << "," << bitsText(*formats[i], texels[i].result.data()) << "\n";
  }
  if (!out) throw std::runtime_error(std::string("writing '") + outPath + "' failed");
  std::cerr << cases.size() << " cases captured into " << outPath << (bad ? ", " + std::to_string(bad) + " bad line(s) skipped" : "")
            << "\n";
  return bad ? 1 : 0;
}

}  // namespace

int runFrames(const char* tracePath, const char* outPath) {
  std::ifstream trace(tracePath, std::ios::binary);
  if (!trace) throw std::runtime_error(std::string("cannot read '") + tracePath + "'");
  std::ofstream out(outPath, std::ios::binary);
  if (!out) throw std::runtime_error(std::string("cannot write '") + outPath + "'");
  oitref::glcheck::GlContext context;
  std::cerr << "GL: " << context.vendor() << " | " << context.renderer() << " | " << context.version() << "\n";
  const size_t calls = oitref::glcheck::replayTrace(context.gl(), trace, out);
  if (!out.flush()) throw std::runtime_error(std::string("writing '") + outPath + "' failed");
  std::cerr << calls << " GL calls replayed; reads in " << outPath << "\n";
  return 0;
}

int runSampling(const char* outPath) {
  std::ofstream out(outPath);
  if (!out) throw std::runtime_error(std::string("cannot write '") + outPath + "'");
  oitref::glcheck::GlContext context;
  std::cerr << "GL: " << context.vendor() << " | " << context.renderer() << " | " << context.version() << "\n";
  oitref::glcheck::captureSampling(context.gl(), out);
  if (!out.flush()) throw std::runtime_error(std::string("writing '") + outPath + "' failed");
  std::cerr << "sampling experiments in " << outPath << "\n";
  return 0;
}

// NVIDIA's driver keeps compiled shaders in a disk cache, and a shader loaded from it can compute
// other bits than the same shader compiled afresh (on the H200, driver 580.159.04: cached replays
// of a scene's trace differed from the first in 3 of 5 scenes). Captures turn the cache off, which
// removes that difference; replays of shaders calling pow/exp/log still vary now and then
// (docs/nvidia.md, "The GPU's frames are not reproducible run to run"). A caller who sets
// __GL_SHADER_DISK_CACHE keeps its value.
static void disableShaderDiskCache() {
  setenv("__GL_SHADER_DISK_CACHE", "0", /*overwrite=*/0);
  std::cerr << "__GL_SHADER_DISK_CACHE=" << std::getenv("__GL_SHADER_DISK_CACHE") << "\n";
}

int main(int argc, char** argv) {
  disableShaderDiskCache();
  const bool blend = argc == 4 && std::strcmp(argv[1], "blend") == 0;
  const bool frames = argc == 4 && std::strcmp(argv[1], "frames") == 0;
  const bool sampling = argc == 3 && std::strcmp(argv[1], "sampling") == 0;
  if (!blend && !frames && !sampling) {
    std::cerr << "usage: oitref-gpu-capture blend CASES.csv OUT.csv\n"
                 "  runs each case on this machine's GPU (headless EGL) and writes CASES.csv's lines with\n"
                 "  gpu_dst_bits and gpu_result_bits added (compare with `oitref blend --cases OUT.csv`)\n"
                 "       oitref-gpu-capture frames TRACE READS\n"
                 "  replays a GL trace (`oitref glcheck scene --record-trace`) and writes every read's texels\n"
                 "  (compare with `oitref glcheck scene ... --gpu-reads READS`)\n"
                 "       oitref-gpu-capture sampling OUT.csv\n"
                 "  measures the texture unit's LINEAR weights, mipmap fraction, implicit level of detail and\n"
                 "  NEAREST addressing (docs/nvidia.md, \"Texture sampling\")\n";
    return 2;
  }
  try {
    if (sampling) return runSampling(argv[2]);
    return blend ? runBlend(argv[2], argv[3]) : runFrames(argv[2], argv[3]);
  } catch (const std::exception& e) {
    std::cerr << "oitref-gpu-capture: " << e.what() << "\n";
    return 1;
  }
}
