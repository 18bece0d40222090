// Image files: PFM layout (written by hand) and EXR/PNG through OpenImageIO, read back.
#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "oitref/oit/image_io.h"

using namespace oitref;

TEST_CASE("image io: PFM is RGB fp32 with the bottom row first, EXR and PNG read back top row first", "[io]") {
  const auto dir = std::filesystem::temp_directory_path() / "oitref-io-test";
  std::filesystem::create_directories(dir);
  Image img(makeFormat(FormatId::RGBA32F), 3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) img.store(x, y, {float(x), float(y), 0.5f, 1.0f}, exactProfile());
  const std::string pfm = (dir / "a.pfm").string();
  writeImage(pfm, img);
  std::ifstream in(pfm, std::ios::binary);
  std::string magic, scale;
  int w = 0, h = 0;
  in >> magic >> w >> h >> scale;
  in.get();
  CHECK(magic == "PF");
  CHECK(w == 3);
  CHECK(h == 2);
  CHECK(scale == "-1.0");  // little-endian
  float data[18];
  in.read(reinterpret_cast<char*>(data), sizeof data);
  CHECK(data[3 * 1 + 0] == 1.0f);  // bottom row (y = 0), x = 1
  CHECK(data[3 * 3 + 1] == 1.0f);  // second row from the bottom is y = 1
  // EXR through OIIO: the first scanline of the file is the top row (y = 1).
  const std::string exr = (dir / "a.exr").string();
  writeImage(exr, img);
  auto reader = OIIO::ImageInput::open(exr);
  REQUIRE(reader);
  float pixels[24];
  REQUIRE(reader->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, pixels));
  CHECK(pixels[1] == 1.0f);       // top-left: y = 1
  CHECK(pixels[4 * 3 + 1] == 0.0f);  // bottom-left: y = 0
  CHECK_THROWS_WITH(writeImage((dir / "b.png").string(), img), Catch::Contains("write it as .exr"));
  CHECK_THROWS_WITH(writeImage((dir / "c.pfm").string(), Image(makeFormat(FormatId::RGBA16F), 2, 2)),
                    Catch::Contains("PFM holds fp32"));
}

TEST_CASE("image io: files appear complete under their final name or not at all", "[io]") {
  const auto dir = std::filesystem::temp_directory_path() / "oitref-io-atomic";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  Image img(makeFormat(FormatId::RGBA8), 4, 4);
  // A write that fails half-way (a 1x1 PNG cannot be written into a missing folder; a PFM of a
  // folder's name cannot replace the folder) leaves neither the final name nor a temporary.
  CHECK_THROWS_WITH(writeImage((dir / "missing" / "a.png").string(), img), Catch::Contains("missing/a.png"));
  std::filesystem::create_directories(dir / "taken.pfm");
  Image f(makeFormat(FormatId::RGBA32F), 2, 2);
  CHECK_THROWS(writeImage((dir / "taken.pfm").string(), f));
  CHECK_THROWS(writeTextFile((dir / "taken.pfm").string(), "text"));
  CHECK(std::filesystem::is_directory(dir / "taken.pfm"));
  // Successful writes leave only the final files.
  writeImage((dir / "a.png").string(), img);
  writeImage((dir / "a.exr").string(), f);
  writeTextFile((dir / "manifest.txt").string(), "x 1\n");
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  CHECK(names == std::vector<std::string>{"a.exr", "a.png", "manifest.txt", "taken.pfm"});
}

TEST_CASE("image io: 8- and 16-bit files read back as k / (2^n − 1), correctly rounded", "[io]") {
  const auto dir = std::filesystem::temp_directory_path() / "oitref-io-read";
  std::filesystem::create_directories(dir);
  Image img(makeFormat(FormatId::RGBA8), 256, 1);
  for (int k = 0; k < 256; ++k) std::memset(img.texel(k, 0), k, 4);
  const std::string png = (dir / "ramp.png").string();
  writeImage(png, img);
  const ImageFile back = readImage(png);
  REQUIRE(back.channels == 4);
  for (int k = 0; k < 256; ++k) {
    INFO("k = " << k);
    CHECK(back.image.fetch(k, 0) == img.fetch(k, 0));  // the RGBA8 decode of the same bits
  }
  // 16-bit: every k through OIIO's writer, against the correctly rounded quotient.
  std::vector<uint16_t> ramp(65536);
  for (size_t k = 0; k < ramp.size(); ++k) ramp[k] = uint16_t(k);
  const std::string png16 = (dir / "ramp16.png").string();
  {
    auto out = OIIO::ImageOutput::create(png16);
    REQUIRE(out);
    REQUIRE(out->open(png16, OIIO::ImageSpec(256, 256, 1, OIIO::TypeDesc::UINT16)));
    REQUIRE(out->write_image(OIIO::TypeDesc::UINT16, ramp.data()));
    out->close();
  }
  const ImageFile grey = readImage(png16);
  REQUIRE(grey.channels == 1);
  // f is the correctly rounded k / 65535 when no neighbouring float is nearer; f·65535 is exact
  // in double (24 + 16 bits), so the distances are compared exactly.
  auto distance = [](float f, int k) { return std::fabs(double(f) * 65535.0 - double(k)); };
  int wrong = 0;
  for (int k = 0; k < 65536; ++k) {
    const int x = k % 256, topRow = k / 256;
    const float f = grey.image.fetch(x, 255 - topRow).r;
    const double d = distance(f, k);
    wrong += d > distance(std::nextafter(f, 2.0f), k) || d > distance(std::nextafter(f, -1.0f), k);
  }
  CHECK(wrong == 0);
}
