// liboitref_imageio.so: the one file that includes OpenImageIO, built as a module that oitref
// loads the first time it reads or writes an image file (image_codec.cpp).
//
// Why a module: Debian 12's libOpenImageIO needs some 260 shared libraries (OpenCV, FFmpeg,
// DCMTK, …), and a program linked against it spends 0.4–0.5 s in the dynamic loader before
// main() on this machine — every `oitref` run, every test program, whether it touches an image
// or not. Loaded on demand, only the runs that read or write images pay it.
//
// The interface is plain C (image_codec_abi.h), so the module and the program share no C++ types.
#include <algorithm>
#include <cstring>
#include <string>

#include <OpenImageIO/imageio.h>

#include "io/image_codec_abi.h"

namespace {

OIIO::TypeDesc typeOf(int sample) {
  switch (sample) {
    case OITREF_IMAGEIO_UINT8: return OIIO::TypeDesc::UINT8;
    case OITREF_IMAGEIO_UINT16: return OIIO::TypeDesc::UINT16;
    case OITREF_IMAGEIO_HALF: return OIIO::TypeDesc::HALF;
    default: return OIIO::TypeDesc::FLOAT;
  }
}

int sampleOf(const OIIO::TypeDesc& type) {
  if (type == OIIO::TypeDesc::UINT8) return OITREF_IMAGEIO_UINT8;
  if (type == OIIO::TypeDesc::UINT16) return OITREF_IMAGEIO_UINT16;
  if (type == OIIO::TypeDesc::HALF) return OITREF_IMAGEIO_HALF;
  if (type == OIIO::TypeDesc::FLOAT) return OITREF_IMAGEIO_FLOAT;
  return OITREF_IMAGEIO_OTHER;
}

void copyText(const std::string& text, char* out, size_t size) {
  if (size == 0) return;
  const size_t n = std::min(text.size(), size - 1);
  std::memcpy(out, text.data(), n);
  out[n] = '\0';
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int oitref_imageio_abi(void) { return OITREF_IMAGEIO_ABI; }

__attribute__((visibility("default"))) void* oitref_imageio_open(const char* path, oitref_imageio_spec* spec,
                                                                 char* error, size_t error_size) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    copyText(OIIO::geterror(), error, error_size);
    return nullptr;
  }
  const OIIO::ImageSpec& s = in->spec();
  spec->width = s.width;
  spec->height = s.height;
  spec->channels = s.nchannels;
  spec->sample = sampleOf(s.format);
  spec->bits_per_sample = s.get_int_attribute("oiio:BitsPerSample", int(s.format.size() * 8));
  copyText(in->format_name(), spec->format_name, sizeof spec->format_name);
  return in.release();
}

__attribute__((visibility("default"))) int oitref_imageio_read(void* reader, int sample, void* pixels, char* error,
                                                               size_t error_size) {
  auto* in = static_cast<OIIO::ImageInput*>(reader);
  if (in->read_image(0, 0, 0, in->spec().nchannels, typeOf(sample), pixels)) return 1;
  copyText(in->geterror(), error, error_size);
  return 0;
}

__attribute__((visibility("default"))) void oitref_imageio_close(void* reader) {
  auto* in = static_cast<OIIO::ImageInput*>(reader);
  in->close();
  delete in;
}

__attribute__((visibility("default"))) int oitref_imageio_can_write(const char* path) {
  return OIIO::ImageOutput::create(path) != nullptr;
}

__attribute__((visibility("default"))) int oitref_imageio_write(const char* path, int width, int height, int channels,
                                                                int sample, const void* top_row, ptrdiff_t pixel_stride,
                                                                ptrdiff_t row_stride, char* error, size_t error_size) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) {
    copyText(OIIO::geterror(), error, error_size);
    return 0;
  }
  const OIIO::TypeDesc type = typeOf(sample);
  OIIO::ImageSpec spec(width, height, channels, type);
  if (channels == 4) spec.alpha_channel = 3;
  // OIIO stamps the current time into EXR headers unless told otherwise; a reference image must
  // be the same file every time it is written.
  spec.attribute("DateTime", "");
  spec.attribute("Software", "oitref");
  if (out->open(path, spec) && out->write_image(type, top_row, pixel_stride, row_stride) && out->close()) return 1;
  copyText(out->geterror(), error, error_size);
  return 0;
}

}  // extern "C"
