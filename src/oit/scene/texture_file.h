// Texture images for scenes: a file read through OpenImageIO into an RGBA8 Texture2D with its
// mipmaps (Texture2D::generateMipmaps).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "oitref/core/texture.h"

namespace oitref::detail {

// The file's first row is its top one and becomes the texture's last row (t = 1), so that
// t = 0 is the image's bottom edge, as OBJ, glTF-through-Assimp and the thesis's stb_image-loaded
// textures with flipped rows use it. Channels: grey → (g, g, g, 1), grey + alpha → (g, g, g, a),
// RGB → (r, g, b, 1), a fourth channel is alpha, more are ignored. 8-bit samples are the bytes;
// 16-bit ones k become ⌊(255k + 32767) / 65535⌋ (k·255/65535 rounded to nearest); floating-point
// ones are clamped to [0, 1] and v·255 rounded to nearest (ties to even). Throws SceneError
// naming the file and what is wrong, before reading any pixel when the decoded image would not
// fit in `memoryLimit` or a PNG file is too small for the size its header declares.
std::shared_ptr<const Texture2D> loadTextureFile(const std::string& path, TextureFormat format,
                                                 uint64_t memoryLimit = UINT64_MAX);

}  // namespace oitref::detail
