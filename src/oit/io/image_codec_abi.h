// The C interface between oitref and its image module, liboitref_imageio.so (imageio_module.cpp,
// loaded by image_codec.cpp). Plain C types only: the module is built with OpenImageIO's headers,
// the program without them. OITREF_IMAGEIO_ABI changes whenever anything below does; the
// loader refuses a module of another one.
#pragma once

#include <stddef.h>

#define OITREF_IMAGEIO_ABI 1

// Sample types of a file or of the pixels handed over.
#define OITREF_IMAGEIO_OTHER 0
#define OITREF_IMAGEIO_UINT8 1
#define OITREF_IMAGEIO_UINT16 2
#define OITREF_IMAGEIO_HALF 3
#define OITREF_IMAGEIO_FLOAT 4

#ifdef __cplusplus
extern "C" {
#endif

struct oitref_imageio_spec {
  int width, height, channels;
  int sample;           // the file's sample type (OITREF_IMAGEIO_*)
  int bits_per_sample;  // as stored (a 1-bit PNG: 1)
  char format_name[32];  // "png", "openexr", …
};

int oitref_imageio_abi(void);
// A reader of the file, or null with the reason in `error`.
void* oitref_imageio_open(const char* path, struct oitref_imageio_spec* spec, char* error, size_t error_size);
// All channels of the first subimage, top row first, converted to `sample`: 1, or 0 with the reason.
int oitref_imageio_read(void* reader, int sample, void* pixels, char* error, size_t error_size);
void oitref_imageio_close(void* reader);
// Whether a writer exists for the path's extension.
int oitref_imageio_can_write(const char* path);
// Writes width × height pixels of `channels` samples of type `sample` (alpha the fourth, if
// any), the top row at top_row, with the given strides in bytes: 1, or 0 with the reason.
int oitref_imageio_write(const char* path, int width, int height, int channels, int sample, const void* top_row,
                         ptrdiff_t pixel_stride, ptrdiff_t row_stride, char* error, size_t error_size);

#ifdef __cplusplus
}
#endif
