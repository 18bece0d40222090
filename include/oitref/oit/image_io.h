// Render targets to and from files through OpenImageIO, top row first in the file.
//  * 8-bit UNORM targets (r8, rg8, rgba8): their bytes as they are (PNG, or any 8-bit format).
//  * fp16 targets: EXR HALF channels holding the target's own bits.
//  * fp32 targets: EXR FLOAT channels holding the target's own bits.
//  * other formats (rgb10a2, r11g11b10f, minifloats): their exact decoded values as EXR FLOAT.
//  * fp32 and decoded formats may also go to PFM (RGB or grey: an RGBA image loses its alpha).
// Files are written to a temporary name beside the destination and renamed, so an interrupted run
// never leaves a truncated image under the final name.
#pragma once

#include <string>

#include "oitref/core/image.h"

namespace oitref {

// Throws std::runtime_error naming the file and the reason: an extension no writer takes (the
// extension's case does not matter: .PNG is PNG), a format the file type cannot hold, a folder
// that does not exist or is not one.
void writeImage(const std::string& path, const Image& image);
// What writeImage checks before it writes anything: the folder, and a writer for the extension
// (a command checks its output path this way before its work).
void checkImagePath(const std::string& path);
// The path's extension in lower case (".png" for "a.PNG").
std::string lowerExtension(const std::string& path);

// An image file read back as fp32 values: RGBA32F for 3 or 4 channels (alpha 1 when the file
// has none), RG32F or R32F for 2 or 1; `channels` is what the file had. Rows are stored bottom
// first, as every oitref Image. 8-bit files read as v/255 exactly, half floats exactly.
struct ImageFile {
  Image image;
  int channels = 0;
};
// EXR, PNG, PFM or anything OpenImageIO reads. Throws std::runtime_error naming the file.
ImageFile readImage(const std::string& path);
// Text files (manifests, CSV results) written the same way: a temporary, then a rename.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace oitref
