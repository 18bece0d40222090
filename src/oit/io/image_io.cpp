#include "oitref/oit/image_io.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "io/image_codec.h"

namespace oitref {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

namespace {

// The temporary a file is written to first, in the destination's folder — which must be one.
std::filesystem::path tempBeside(const std::filesystem::path& final) {
  const std::filesystem::path folder = final.parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw std::runtime_error(final.string() + ": cannot write it: '" + folder.string() + "' " +
                             (std::filesystem::exists(folder, ec) ? "is not a folder" : "does not exist"));
  if (std::filesystem::is_directory(final, ec)) throw std::runtime_error(final.string() + ": is a folder, not a file name");
  return folder / ("." + final.stem().string() + ".tmp" + std::to_string(::getpid()) + final.extension().string());
}

// The complete temporary becomes the final file in one rename; if that fails, nothing is left.
void commit(const std::filesystem::path& temp, const std::filesystem::path& final) {
  std::error_code ec;
  std::filesystem::rename(temp, final, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw std::runtime_error(final.string() + ": cannot replace it: " + ec.message());
  }
}

// Portable float map: "PF" (RGB) or "Pf" (grey), width and height, a negative scale for
// little-endian data, then fp32 rows from the bottom up — the order oitref stores rows in.
// One or two channels are written as grey (the first), three or four as RGB.
void writePfm(const std::string& path, const Image& image) {
  const int w = image.width(), h = image.height();
  const bool grey = image.format().channels < 3;
  const std::filesystem::path final(path), temp = tempBeside(final);
  {
    std::ofstream out(temp, std::ios::binary);
    out << (grey ? "Pf" : "PF") << "\n" << w << " " << h << "\n-1.0\n";
    std::vector<float> row(size_t(w) * (grey ? 1 : 3));
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const glm::vec4 v = image.fetch(x, y);
        for (int c = 0; c < (grey ? 1 : 3); ++c) row[size_t(x) * (grey ? 1 : 3) + size_t(c)] = v[c];
      }
      out.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size() * sizeof(float)));
    }
    if (!out) {
      std::filesystem::remove(temp);
      throw std::runtime_error(path + ": write failed");
    }
  }
  commit(temp, final);
}

}  // namespace

void writeTextFile(const std::string& path, const std::string& text) {
  const std::filesystem::path final(path), temp = tempBeside(final);
  {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    if (!out) {
      std::filesystem::remove(temp);
      throw std::runtime_error(path + ": write failed");
    }
  }
  commit(temp, final);
}

void checkImagePath(const std::string& path) {
  tempBeside(path);  // the folder
  const std::string ext = lowerExtension(path);
  if (ext != ".pfm" && !detail::imageWriterExists(path))
    throw std::runtime_error(path + ": no image writer for the extension '" + ext +
                             "' (write .png, .exr or .pfm, or another format OpenImageIO writes: .tif, .hdr, …)");
}

void writeImage(const std::string& path, const Image& image) {
  const Format& f = image.format();
  const int w = image.width(), h = image.height(), channels = f.channels;
  const ChannelEncoding enc = f.encoding();
  const bool rawBytes = (enc == ChannelEncoding::Unorm && !f.isPacked()) || enc == ChannelEncoding::Half ||
                        enc == ChannelEncoding::Float32;
  using detail::ImageSample;
  const ImageSample type = enc == ChannelEncoding::Unorm && !f.isPacked()
                               ? (f.unormBits(0) == 16 ? ImageSample::UInt16 : ImageSample::UInt8)
                           : enc == ChannelEncoding::Half ? ImageSample::Half
                                                          : ImageSample::Float;
  const std::string ext = lowerExtension(path);
  const bool pfm = ext == ".pfm";
  checkImagePath(path);  // a writer for the extension first: an unknown one is not a question of bits
  if (type != ImageSample::UInt8 && !(type == ImageSample::UInt16 && ext == ".png") && ext != ".exr" && !pfm)
    throw std::runtime_error(path + ": format " + f.name() + " holds values beyond 8 bits; write it as .exr or .pfm");
  if (pfm && (enc == ChannelEncoding::Half || f.isUnorm()))
    throw std::runtime_error(path + ": PFM holds fp32 values; write " + f.name() + " as .exr or .png");
  if (pfm) {
    writePfm(path, image);
    return;
  }

  // Pixels in memory, bottom row first (GL window order); a negative y stride flips on output.
  std::vector<float> decoded;
  const uint8_t* base = image.bytes().data();
  std::ptrdiff_t pixelStride = std::ptrdiff_t(image.bytesPerTexel());
  if (!rawBytes) {
    decoded.resize(size_t(w) * h * channels);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::vec4 v = image.fetch(x, y);
        for (int c = 0; c < channels; ++c) decoded[(size_t(y) * w + x) * channels + c] = v[c];
      }
    base = reinterpret_cast<const uint8_t*>(decoded.data());
    pixelStride = std::ptrdiff_t(sizeof(float) * channels);
  }
  const std::ptrdiff_t rowStride = pixelStride * w;
  const uint8_t* topRow = base + size_t(h - 1) * size_t(rowStride);

  const std::filesystem::path final(path);
  const std::filesystem::path temp = tempBeside(final);
  std::string error;
  if (!detail::writeImagePixels(temp.string(), w, h, channels, type, topRow, pixelStride, -rowStride, error)) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw std::runtime_error(path + ": " + error);
  }
  commit(temp, final);
}

ImageFile readImage(const std::string& path) {
  std::string error;
  const auto in = detail::ImageFileReader::open(path, error);
  if (!in) throw std::runtime_error(path + ": cannot read the image: " + error);
  const detail::ImageFileSpec& spec = in->spec();
  const int w = spec.width, h = spec.height, channels = spec.channels;
  if (w < 1 || h < 1 || w > Image::kMaxDimension || h > Image::kMaxDimension)
    throw std::runtime_error(path + ": image size " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." +
                             std::to_string(Image::kMaxDimension));
  if (channels < 1) throw std::runtime_error(path + ": the image has no channels");
  // UNORM files are read as their integers and divided here, k / (2^n − 1) correctly rounded
  // (OpenImageIO's own conversion multiplies by a rounded reciprocal).
  const size_t samples = size_t(w) * size_t(h) * size_t(channels);
  std::vector<float> pixels(samples);
  const bool u8 = spec.sample == detail::ImageSample::UInt8, u16 = spec.sample == detail::ImageSample::UInt16;
  bool ok = true;
  if (u8 || u16) {
    std::vector<uint16_t> ints(samples);
    ok = in->read(detail::ImageSample::UInt16, ints.data(), error);
    // Read as 16 bits: an 8-bit k arrives as k·257, so k·257 / 65535 = k / 255 either way.
    for (size_t i = 0; i < samples; ++i) pixels[i] = float(double(ints[i]) / 65535.0);
  } else {
    ok = in->read(detail::ImageSample::Float, pixels.data(), error);
  }
  if (!ok) throw std::runtime_error(path + ": " + error);
  const int kept = std::min(channels, 4);
  ImageFile file{Image(makeFormat(kept == 1 ? FormatId::R32F : kept == 2 ? FormatId::RG32F : FormatId::RGBA32F), w, h),
                 channels};
  const Profile exact = exactProfile();
  for (int row = 0; row < h; ++row)
    for (int x = 0; x < w; ++x) {
      const float* p = &pixels[(size_t(row) * size_t(w) + size_t(x)) * size_t(channels)];
      glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f);
      for (int c = 0; c < kept; ++c) v[c] = p[c];
      file.image.store(x, h - 1 - row, v, exact);  // the file's first row is the top one
    }
  return file;
}

}  // namespace oitref
