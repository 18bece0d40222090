#include "scene/texture_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "io/image_codec.h"
#include "oitref/core/memory_limit.h"
#include "oitref/oit/scene.h"

namespace oitref::detail {
namespace {

constexpr int kMaxTextureSize = 16384;  // GL's usual MAX_TEXTURE_SIZE; 1 GiB of RGBA8 at most

uint8_t unorm8FromUnorm16(uint16_t k) { return uint8_t((255u * k + 32767u) / 65535u); }
uint8_t unorm8FromFloat(float v) {
  const double c = std::isnan(v) ? 0.0 : std::clamp(double(v), 0.0, 1.0);
  return uint8_t(std::nearbyint(c * 255.0));
}

}  // namespace

std::shared_ptr<const Texture2D> loadTextureFile(const std::string& path, TextureFormat format, uint64_t memoryLimit) {
  if (!std::filesystem::is_regular_file(path)) throw SceneError("texture '" + path + "' does not exist or is not a file");
  std::string error;
  const auto in = ImageFileReader::open(path, error);
  if (!in) throw SceneError("texture '" + path + "': cannot read the image: " + error);
  const ImageFileSpec& spec = in->spec();
  const int w = spec.width, h = spec.height, channels = spec.channels;
  if (w < 1 || h < 1 || w > kMaxTextureSize || h > kMaxTextureSize)
    throw SceneError("texture '" + path + "': size " + std::to_string(w) + "x" + std::to_string(h) +
                     " is outside 1.." + std::to_string(kMaxTextureSize));
  if (channels < 1) throw SceneError("texture '" + path + "': the image has no channels");
  const size_t samples = size_t(w) * size_t(h) * size_t(channels);
  // Before any pixel is read (a 74-byte PNG declaring 16384x16384 took 1.2 GB and 3.5 s to fail):
  // the file must be able to hold what its header declares, and the decoded image must fit.
  const int bits = spec.bitsPerSample;
  if (spec.formatName == "png") {
    // Each row is a filter byte and its packed samples; deflate packs at most 1032 bytes into
    // one (a 258-byte match in two 1-bit codes), so no PNG holds more than 1032 raw bytes a byte.
    const uint64_t raw = uint64_t(h) * (1 + (uint64_t(w) * uint64_t(channels) * uint64_t(bits) + 7) / 8);
    const uint64_t fileBytes = std::filesystem::file_size(path);
    if (fileBytes * 1032 < raw)
      throw SceneError("texture '" + path + "': its PNG header declares " + std::to_string(w) + "x" + std::to_string(h) +
                       " with " + std::to_string(channels) + " channels of " + std::to_string(bits) + " bits, " +
                       std::to_string(raw) + " bytes before compression, which no PNG of " + std::to_string(fileBytes) +
                       " bytes can hold (deflate packs at most 1032 bytes into one)");
  }
  const uint64_t sampleBytes = spec.sample == ImageSample::UInt8 ? 1 : spec.sample == ImageSample::UInt16 ? 2 : 4;
  const uint64_t need = uint64_t(samples) * (sampleBytes + (sampleBytes > 1 ? 1 : 0)) + uint64_t(w) * uint64_t(h) * 4;
  if (need > memoryLimit)
    throw SceneError("texture '" + path + "': " + std::to_string(w) + "x" + std::to_string(h) + " with " +
                     std::to_string(channels) + " channels needs at least " + formatBytes(need) +
                     " to load, above the memory limit of " + formatBytes(memoryLimit) + " (--memory-limit)");
  std::vector<uint8_t> bytes(samples);
  bool ok = true;
  if (spec.sample == ImageSample::UInt8) {
    ok = in->read(ImageSample::UInt8, bytes.data(), error);
  } else if (spec.sample == ImageSample::UInt16) {
    std::vector<uint16_t> k(samples);
    ok = in->read(ImageSample::UInt16, k.data(), error);
    std::transform(k.begin(), k.end(), bytes.begin(), unorm8FromUnorm16);
  } else {
    std::vector<float> v(samples);
    ok = in->read(ImageSample::Float, v.data(), error);
    std::transform(v.begin(), v.end(), bytes.begin(), unorm8FromFloat);
  }
  if (!ok) throw SceneError("texture '" + path + "': " + error);
  std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
  for (int row = 0; row < h; ++row)
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = &bytes[(size_t(row) * size_t(w) + size_t(x)) * size_t(channels)];
      uint8_t* t = &rgba[(size_t(h - 1 - row) * size_t(w) + size_t(x)) * 4];
      if (channels <= 2) t[0] = t[1] = t[2] = p[0], t[3] = channels == 2 ? p[1] : 255;
      else t[0] = p[0], t[1] = p[1], t[2] = p[2], t[3] = channels >= 4 ? p[3] : 255;
    }
  auto texture = std::make_shared<Texture2D>(format, w, h, std::move(rgba));
  texture->generateMipmaps();
  return texture;
}

}  // namespace oitref::detail
