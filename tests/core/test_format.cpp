// Texel layouts, hand-derived from the GL packed-type tables (GL 4.6 §8.4.4.2, table 8.8).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <vector>

#include "oitref/core/format.h"
#include "oitref/core/image.h"

using namespace oitref;

namespace {

uint32_t word(const uint8_t* t) {
  uint32_t w;
  std::memcpy(&w, t, 4);
  return w;
}

std::string bitsOf(const std::string& format, glm::vec4 v, const Profile& p = exactProfile()) {
  uint8_t t[16] = {};
  const Format f = parseFormat(format);
  encodeTexel(f, v, p, t);
  return texelBitsToString(f, t);
}

}  // namespace

TEST_CASE("format: packed layouts put each channel where GL's _REV types do", "[format]") {
  const Format f = makeFormat(FormatId::RGB10A2);
  uint8_t t[4];
  encodeTexel(f, {1, 0, 0, 0}, exactProfile(), t);
  CHECK(word(t) == 0x000003ffu);  // R bits 0–9
  encodeTexel(f, {0, 1, 0, 0}, exactProfile(), t);
  CHECK(word(t) == 0x000ffc00u);  // G bits 10–19
  encodeTexel(f, {0, 0, 1, 0}, exactProfile(), t);
  CHECK(word(t) == 0x3ff00000u);  // B bits 20–29
  encodeTexel(f, {0, 0, 0, 1}, exactProfile(), t);
  CHECK(word(t) == 0xc0000000u);  // A bits 30–31
  encodeTexel(f, {0, 0, 0, 0.5f}, exactProfile(), t);
  CHECK(word(t) == 0x80000000u);  // 0.5·3 = 1.5 -> 2 (ties to even)

  const Format g = makeFormat(FormatId::R11G11B10F);
  encodeTexel(g, {1, 0, 0, 0}, exactProfile(), t);
  CHECK(word(t) == 0x000003c0u);  // F11 1.0 = exponent 15 << 6, bits 0–10
  encodeTexel(g, {0, 1, 0, 0}, exactProfile(), t);
  CHECK(word(t) == 0x001e0000u);  // bits 11–21
  encodeTexel(g, {0, 0, 1, 0}, exactProfile(), t);
  CHECK(word(t) == 0x78000000u);  // F10 1.0 = 15 << 5, bits 22–31
  CHECK(texelBitsToString(g, t) == "78000000");
}

TEST_CASE("format: array formats store little-endian channels in order", "[format]") {
  CHECK(bitsOf("rgba16f", {1, 0.5f, 0, 1}) == "3c00 3800 0000 3c00");
  CHECK(bitsOf("rgba8", {1, 0.5f, 0, 1}) == "ff 80 00 ff");
  // UNORM16 (GL 4.6 §2.3.5.2): 0.5·65535 = 32767.5 ties to even 32768; fp32 1/3 is
  // 0.3333333433, ·65535 = 21845.0007 -> 21845 = 0x5555; out of range clamps; NaN -> 0.
  CHECK(bitsOf("rgba16", {1, 0.5f, 1.0f / 3.0f, 2}) == "ffff 8000 5555 ffff");
  CHECK(bitsOf("rg16", {-1, std::nanf(""), 0, 0}) == "0000 0000");
  CHECK(bitsOf("rg32f", {1, -2, 0, 0}) == "3f800000 c0000000");
  CHECK(bitsOf("r16f", {65520, 0, 0, 0}) == "7c00");
  CHECK(bitsOf("r16f", {65520, 0, 0, 0}, llvmpipeProfile()) == "7bff");
  CHECK(bitsOf("rgba:e8m7", {1, -2, 0.1f, 3}) == "3f80 c000 3dcd 4040");
  CHECK(bitsOf("rg:e4m3fn", {448, -1000, 0, 0}) == "7e fe");
  CHECK(parseFormat("rgba16f").bytesPerTexel() == 8);
  CHECK(parseFormat("rgba16").bytesPerTexel() == 8);
  CHECK(parseFormat("r16").bytesPerTexel() == 2);
  CHECK(parseFormat("r11g11b10f").bytesPerTexel() == 4);
  CHECK(parseFormat("rgba:e4m3fn").bytesPerTexel() == 4);
  CHECK(parseFormat("rgb:e7m16").bytesPerTexel() == 12);
}

TEST_CASE("format: missing channels read as GL fills them (0, 0, 1)", "[format]") {
  for (const char* name : {"r8", "r16f", "r32f", "rg8", "rg16f", "r11g11b10f", "r:e5m2"}) {
    const Format f = parseFormat(name);
    uint8_t t[16] = {};
    encodeTexel(f, {0.5f, 0.25f, 0.75f, 0.125f}, exactProfile(), t);
    const glm::vec4 v = decodeTexel(f, t);
    INFO(name);
    if (f.channels < 2) CHECK(v.g == 0.0f);
    if (f.channels < 3) CHECK(v.b == 0.0f);
    CHECK(v.a == 1.0f);
  }
}

TEST_CASE("format: names parse and unknown names get the list", "[format]") {
  for (const std::string& n : builtinFormatNames()) CHECK(parseFormat(n).name() == n);
  CHECK(parseFormat("rgba:e8m7").name() == "rgba:e8m7");
  try {
    parseFormat("rgba12");
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    CHECK_THAT(e.what(), Catch::Contains("rgba16f") && Catch::Contains("unknown format 'rgba12'"));
  }
  CHECK_THROWS_AS(parseFormat("xyz:e5m2"), std::invalid_argument);
}

TEST_CASE("format: write masks on packed formats keep the other channels' bits", "[format]") {
  const Format f = makeFormat(FormatId::RGB10A2);
  uint8_t from[4], to[4];
  encodeTexel(f, {1, 1, 1, 1}, exactProfile(), from);
  encodeTexel(f, {0, 0, 0, 0}, exactProfile(), to);
  mergeTexelChannels(f, from, to, 0b1010);  // G and A
  CHECK(word(to) == 0xc00ffc00u);
  const Format g = makeFormat(FormatId::R11G11B10F);
  encodeTexel(g, {1, 1, 1, 0}, exactProfile(), from);
  encodeTexel(g, {0, 0, 0, 0}, exactProfile(), to);
  mergeTexelChannels(g, from, to, 0b100);  // B only
  CHECK(word(to) == 0x78000000u);
}

TEST_CASE("image: clear and store write the converted bits everywhere", "[format]") {
  Image img(parseFormat("rgba16f"), 5, 3);
  img.clear({0.1f, 1, 2, 65520}, exactProfile());
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) REQUIRE(texelBitsToString(img.format(), img.texel(x, y)) == "2e66 3c00 4000 7c00");
  img.store(4, 2, {0, 0, 0, 0}, exactProfile());
  CHECK(texelBitsToString(img.format(), img.texel(4, 2)) == "0000 0000 0000 0000");
  CHECK(img.sizeBytes() == 5 * 3 * 8);
  CHECK_THROWS_AS(Image(parseFormat("rgba8"), 0, 4), std::invalid_argument);
  CHECK_THROWS_AS(Image(parseFormat("rgba8"), 20000, 4), std::invalid_argument);
}

TEST_CASE("format: every UNORM16 code decodes to k/65535 and encodes back to itself", "[format]") {
  const Format f = parseFormat("r16");
  for (uint32_t k = 0; k <= 0xffff; ++k) {
    const uint8_t in[2] = {uint8_t(k & 0xff), uint8_t(k >> 8)};
    const float v = decodeTexel(f, in).r;
    REQUIRE(double(v) == Approx(double(k) / 65535.0).epsilon(1e-7));
    uint8_t out[2] = {};
    encodeTexel(f, {v, 0, 0, 0}, exactProfile(), out);
    REQUIRE((out[0] | (out[1] << 8)) == int(k));
  }
}

TEST_CASE("Image::fetch gives decodeTexel's bits for every 8-bit code in each UNORM8 layout", "[format]") {
  // fetch reads r8, rg8 and rgba8 inline through the decode table, and fetchRun and fetchRow
  // (rgba8: by a division in vector lanes where built with SSE4.1); decodeTexel is the oracle.
  for (const char* name : {"r8", "rg8", "rgba8"}) {
    const Format f = parseFormat(name);
    Image image(f, 256, 1);
    for (int k = 0; k < 256; ++k)
      for (int c = 0; c < f.channels; ++c) image.texel(k, 0)[c] = uint8_t(k * (2 * c + 1) + 17 * c);
    std::vector<glm::vec4> run(256), row(256);
    std::vector<int> xs(256);
    for (int k = 0; k < 256; ++k) xs[size_t(k)] = 255 - k;
    image.fetchRun(0, 0, 256, run.data());
    image.fetchRow(0, xs.data(), 256, row.data());
    for (int k = 0; k < 256; ++k) {
      const glm::vec4 want = decodeTexel(f, image.texel(k, 0));
      const glm::vec4 got[3] = {image.fetch(k, 0), run[size_t(k)], row[size_t(255 - k)]};
      INFO(name << " texel " << k);
      for (const glm::vec4& g : got) CHECK(std::memcmp(&g, &want, sizeof g) == 0);
    }
  }
}

TEST_CASE("Image::fetch gives decodeTexel's bits for every format, fp32 payloads included", "[format]") {
  // fetch reads fp32 and UNORM8 layouts inline and every other format through its decoder; decodeTexel
  // (the general decoder) is the oracle, bit for bit: a signalling NaN with a payload, −0, a
  // denormal and infinities must come back unchanged.
  const uint32_t specials[] = {0x7f800001u, 0xff812345u, 0x80000000u, 0x00000001u, 0x7f800000u, 0xff800000u,
                               0x3f800000u, 0xc1234567u};
  for (const char* name : {"r32f", "rg32f", "rgba32f", "rgba16f", "rg16f", "r16f", "rgba8", "r8", "rg8", "rgba16",
                           "rgb10a2", "r11g11b10f"}) {
    const Format f = parseFormat(name);
    Image image(f, 3, 2);
    for (size_t i = 0; i < image.sizeBytes(); ++i) {
      // Byte patterns that place each special value in each fp32 channel in turn.
      const uint32_t word = specials[(i / 4) % (sizeof specials / sizeof specials[0])];
      image.texel(0, 0)[i] = uint8_t(word >> (8 * (i % 4)));
    }
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) {
        const glm::vec4 got = image.fetch(x, y), want = decodeTexel(f, image.texel(x, y));
        INFO(name << " texel (" << x << ", " << y << ")");
        CHECK(std::memcmp(&got, &want, sizeof got) == 0);
      }
    // fetchRow (the row decoders) over texels in any order, against decodeTexel too.
    const int xs[5] = {2, 0, 1, 1, 2};
    for (int y = 0; y < 2; ++y) {
      glm::vec4 row[5];
      image.fetchRow(y, xs, 5, row);
      for (int i = 0; i < 5; ++i) {
        const glm::vec4 want = decodeTexel(f, image.texel(xs[i], y));
        INFO(name << " fetchRow texel (" << xs[i] << ", " << y << ")");
        CHECK(std::memcmp(&row[i], &want, sizeof want) == 0);
      }
      // fetchRun: the run from each column to the row's end (fp32 copied at once, the decoders
      // with consecutive texels), every texel against decodeTexel, and nothing written past n.
      for (int x0 = 0; x0 < 3; ++x0) {
        glm::vec4 run[4];
        std::memset(run, 0x5a, sizeof run);
        image.fetchRun(y, x0, 3 - x0, run);
        for (int i = 0; i < 3 - x0; ++i) {
          const glm::vec4 want = decodeTexel(f, image.texel(x0 + i, y));
          INFO(name << " fetchRun texel (" << x0 + i << ", " << y << ")");
          CHECK(std::memcmp(&run[i], &want, sizeof want) == 0);
        }
        for (int b = 16 * (3 - x0); b < int(sizeof run); ++b) CHECK(reinterpret_cast<const uint8_t*>(run)[b] == 0x5a);
      }
    }
  }
}
