// Image files through OpenImageIO, in oitref's image module (liboitref_imageio.so), which is
// loaded the first time a file is read or written: a program that touches no image never loads
// OpenImageIO and its ~260 libraries (0.4–0.5 s at every start; imageio_module.cpp says more).
//
// Where the module is looked for, in order:
//   1. OITREF_IMAGEIO_MODULE, when set: that file alone;
//   2. by name, through the run path of the program or module the code is linked into (an
//      installed `oitref` and Python module carry it; a program built against the installed
//      package gets it from oitref::scene's link options);
//   3. beside that program or module (lib/oitref/ under its folder, or ../<libdir>/oitref/),
//      then in the build folder that compiled this code.
// A module that is not found, or of another interface version, is an error that names every
// place tried.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace oitref::detail {

enum class ImageSample { Other = 0, UInt8 = 1, UInt16 = 2, Half = 3, Float = 4 };

struct ImageFileSpec {
  int width = 0, height = 0, channels = 0;
  ImageSample sample = ImageSample::Other;
  int bitsPerSample = 0;
  std::string formatName;  // "png", "openexr", …
};

// An open image file.
class ImageFileReader {
 public:
  // The reader, or null with the reason in `error` (the module's failure to load throws instead).
  static std::unique_ptr<ImageFileReader> open(const std::string& path, std::string& error);
  ~ImageFileReader();
  ImageFileReader(const ImageFileReader&) = delete;
  ImageFileReader& operator=(const ImageFileReader&) = delete;
  const ImageFileSpec& spec() const { return spec_; }
  // Every channel, top row first, as `sample` (width · height · channels of them): false with
  // the reason in `error`.
  bool read(ImageSample sample, void* pixels, std::string& error);

 private:
  ImageFileReader(void* handle, ImageFileSpec spec) : handle_(handle), spec_(std::move(spec)) {}
  void* handle_;
  ImageFileSpec spec_;
};

// Whether OpenImageIO has a writer for the path's extension.
bool imageWriterExists(const std::string& path);
// Writes the pixels (the top row at topRow, strides in bytes); false with the reason in `error`.
bool writeImagePixels(const std::string& path, int width, int height, int channels, ImageSample sample,
                      const void* topRow, std::ptrdiff_t pixelStride, std::ptrdiff_t rowStride, std::string& error);

}  // namespace oitref::detail
