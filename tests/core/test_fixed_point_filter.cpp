// The `llvmpipe` and `nvidia` texture-filter rules (src/core/texture/fixed_point_filter.cpp) against
// what the devices returned in `oitref-gpu-capture sampling` (tests/data/sampling_*.csv.gz):
// LINEAR weights, mipmap fractions, NEAREST edges, bilinear and trilinear sums, sRGB decoding
// and filtering, and the switch from magnification to minification. The implicit
// level-of-detail experiment is not modelled yet (docs/nvidia.md) and not checked.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "gzip_file.h"
#include "oitref/core/texture.h"

using namespace oitref;

namespace {

struct Sample {
  std::string experiment;
  int index;
  uint32_t bits;
};

std::vector<Sample> samples(const std::string& file) {
  std::istringstream in(test::gunzip(OITREF_SOURCE_DIR "/tests/data/" + file));
  std::vector<Sample> out;
  std::string line;
  std::getline(in, line);  // experiment,index,exact,gpu,gpu_bits
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    out.push_back({f[0], std::stoi(f[1]), uint32_t(std::stoul(f[4], nullptr, 16))});
  }
  return out;
}

// The capture's textures: a 2×1 row of 0 and 255 (every channel), and a 2×2 level 0 of 0 under a
// 1×1 level 1 of 255; clamped to the edge.
Texture2D row() { return Texture2D(TextureFormat::Rgba8, 2, 1, {0, 0, 0, 0, 255, 255, 255, 255}); }
Texture2D twoLevels() {
  Texture2D t(TextureFormat::Rgba8, 2, 2, std::vector<uint8_t>(16, 0));
  t.setLevel(1, TextureLevel{1, 1, {255, 255, 255, 255}});
  return t;
}

// The later experiments' textures: 2×2 of 10, 200 / 90, 255 (and a 1×1 level of 77); a row of
// the 256 codes as sRGB; 2×2 of 0, 255 / 0, 255 over a 1×1 level of 128.
std::vector<uint8_t> grey(std::initializer_list<int> bytes) {
  std::vector<uint8_t> out;
  for (int b : bytes) out.insert(out.end(), 4, uint8_t(b));
  return out;
}
Texture2D quad(bool withLevel) {
  Texture2D t(TextureFormat::Rgba8, 2, 2, grey({10, 200, 90, 255}));
  if (withLevel) t.setLevel(1, TextureLevel{1, 1, grey({77})});
  return t;
}
Texture2D srgbRow() {
  std::vector<uint8_t> codes;
  for (int k = 0; k < 256; ++k) codes.insert(codes.end(), 4, uint8_t(k));
  return Texture2D(TextureFormat::Srgb8Alpha8, 256, 1, codes);
}
Texture2D stripes() {
  Texture2D t(TextureFormat::Rgba8, 2, 2, grey({0, 255, 0, 255}));
  t.setLevel(1, TextureLevel{1, 1, grey({128})});
  return t;
}

// What `rule` returns for a sample, as the capture's shader asked for it (sampling_capture.cpp;
// textureLod gives an explicit level of detail).
float lookup(const Sample& x, TextureFiltering rule) {
  SamplerState sp;
  sp.wrapS = sp.wrapT = WrapMode::ClampToEdge;
  const float i = float(x.index);
  const float s2 = (0.5f + std::fmod(i, 64.0f) / 64.0f + 3.0f / 1024.0f) / 2.0f;  // bilinear(i)
  const float t2 = (0.5f + std::floor(i / 64.0f) / 64.0f + 5.0f / 1024.0f) / 2.0f;
  if (x.experiment == "linear_weight") {
    sp.minFilter = sp.magFilter = TextureFilter::Linear;
    return sampleTexture(row(), sp, (0.5f + i / 4096.0f) / 2.0f, 0.5f, -10.0, rule).r;  // magnified
  }
  if (x.experiment == "mipmap_fraction") {
    sp.minFilter = TextureFilter::LinearMipmapLinear;
    return sampleTexture(twoLevels(), sp, 0.5f, 0.5f, double(i) / 4096.0, rule, true).r;
  }
  if (x.experiment == "bilinear") {
    sp.minFilter = sp.magFilter = TextureFilter::Linear;
    return sampleTexture(quad(false), sp, s2, t2, -10.0, rule).r;
  }
  if (x.experiment == "trilinear") {
    sp.minFilter = TextureFilter::LinearMipmapLinear;
    return sampleTexture(quad(true), sp, s2, (0.5f + 5.0f / 1024.0f) / 2.0f, std::floor(i / 64.0) / 64.0, rule, true).r;
  }
  if (x.experiment == "srgb_decode") {  // red, then from sample 2048 on alpha
    sp.minFilter = sp.magFilter = TextureFilter::Nearest;
    return sampleTexture(srgbRow(), sp, (std::fmod(i, 256.0f) + 0.5f) / 256.0f, 0.5f, -10.0, rule)[x.index >= 2048 ? 3 : 0];
  }
  if (x.experiment == "srgb_linear") {
    sp.minFilter = sp.magFilter = TextureFilter::Linear;
    return sampleTexture(srgbRow(), sp, (std::floor(i / 16.0f) + 0.5f + std::fmod(i, 16.0f) / 16.0f) / 256.0f, 0.5f, -10.0, rule).r;
  }
  if (x.experiment == "magnification_switch") {
    sp.minFilter = TextureFilter::NearestMipmapNearest;
    sp.magFilter = TextureFilter::Linear;
    return sampleTexture(stripes(), sp, 0.375f, 0.5f, (i - 2048.0) / 2048.0, rule, true).r;
  }
  sp.minFilter = sp.magFilter = TextureFilter::Nearest;  // nearest_edge
  return sampleTexture(row(), sp, (1.0f + (i - 2048.0f) / 1048576.0f) / 2.0f, 0.5f, -10.0, rule).r;
}

// How many of an experiment's samples `rule` reproduces, and how many there are.
std::pair<int, int> reproduced(const std::vector<Sample>& recorded, const std::string& experiment, TextureFiltering rule) {
  int same = 0, total = 0;
  for (const Sample& x : recorded) {
    if (x.experiment != experiment) continue;
    const float v = lookup(x, rule);
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    same += bits == x.bits;
    ++total;
  }
  return {same, total};
}

const char* const kExperiments[] = {"linear_weight", "mipmap_fraction", "nearest_edge", "bilinear", "trilinear",
                                    "srgb_decode", "srgb_linear", "magnification_switch"};

}  // namespace

TEST_CASE("texture filters: the nvidia rule reproduces the H200's recorded samples", "[texture]") {
  const auto recorded = samples("sampling_h200.csv.gz");
  // Bit for bit but for the two experiments whose composition is fitted, not exact (docs/nvidia.md).
  const std::map<std::string, int> expected{{"trilinear", 4023}, {"srgb_linear", 4081}};
  int exactElsewhere = 0, llvmpipeElsewhere = 0, total = 0;
  for (const char* e : kExperiments) {
    const auto [same, n] = reproduced(recorded, e, TextureFiltering::Nvidia);
    INFO(e);
    CHECK(n == 4096);
    CHECK(same == (expected.count(e) ? expected.at(e) : n));
    exactElsewhere += reproduced(recorded, e, TextureFiltering::Exact).first;
    llvmpipeElsewhere += reproduced(recorded, e, TextureFiltering::Llvmpipe).first;
    total += n;
  }
  // The rules differ where it shows: neither the exact nor llvmpipe's reproduces most of them.
  CHECK(exactElsewhere < total / 2);
  CHECK(llvmpipeElsewhere < total / 2);
}

TEST_CASE("texture filters: the llvmpipe rule reproduces Mesa's recorded samples bit for bit", "[texture]") {
  const auto recorded = samples("sampling_llvmpipe.csv.gz");
  int exactElsewhere = 0, nvidiaElsewhere = 0, total = 0;
  for (const char* e : kExperiments) {
    const auto [same, n] = reproduced(recorded, e, TextureFiltering::Llvmpipe);
    INFO(e);
    CHECK(n == 4096);
    CHECK(same == n);
    exactElsewhere += reproduced(recorded, e, TextureFiltering::Exact).first;
    nvidiaElsewhere += reproduced(recorded, e, TextureFiltering::Nvidia).first;
    total += n;
  }
  CHECK(exactElsewhere < total / 2);
  CHECK(nvidiaElsewhere < total / 2);
}
