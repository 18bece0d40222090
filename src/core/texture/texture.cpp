// Texture storage, the sRGB transfer function and mipmap generation (include/oitref/core/texture.h).
#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "oitref/core/texture.h"

namespace oitref {

const char* toString(WrapMode m) {
  constexpr const char* names[] = {"repeat", "clamp_to_edge", "mirrored_repeat"};
  return names[size_t(m)];
}
const char* toString(TextureFilter f) {
  constexpr const char* names[] = {"nearest",
                                   "linear",
                                   "nearest_mipmap_nearest",
                                   "linear_mipmap_nearest",
                                   "nearest_mipmap_linear",
                                   "linear_mipmap_linear"};
  return names[size_t(f)];
}
WrapMode parseWrapMode(const std::string& name) {
  for (WrapMode m : {WrapMode::Repeat, WrapMode::ClampToEdge, WrapMode::MirroredRepeat})
    if (name == toString(m)) return m;
  throw std::invalid_argument("unknown wrap mode '" + name + "' (repeat, clamp_to_edge, mirrored_repeat)");
}
TextureFilter parseTextureFilter(const std::string& name) {
  for (int f = 0; f <= int(TextureFilter::LinearMipmapLinear); ++f)
    if (name == toString(TextureFilter(f))) return TextureFilter(f);
  throw std::invalid_argument("unknown texture filter '" + name +
                              "' (nearest, linear, nearest_mipmap_nearest, linear_mipmap_nearest, "
                              "nearest_mipmap_linear, linear_mipmap_linear)");
}

// §8.24: c_l = c_s / 12.92 for c_s ≤ 0.04045, else ((c_s + 0.055) / 1.055)^2.4.
double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
// Its inverse (§17.3.7's encoding for sRGB framebuffers): 12.92·c_l below 0.0031308, else
// 1.055·c_l^(1/2.4) − 0.055.
double linearToSrgb(double c) { return c < 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

namespace {
// A stored byte as the filter reads it: k / (2^8 − 1) (§2.3.5.1), the colour channels of an sRGB
// texture then decoded (§8.24); alpha is linear in both formats. Texel reads and mipmap
// generation both go through it.
double decodeChannel(TextureFormat format, uint8_t byte, int channel) {
  const double c = byte / 255.0;
  return format == TextureFormat::Srgb8Alpha8 && channel < 3 ? srgbToLinear(c) : c;
}
}  // namespace

int lastMipmapLevel(int width, int height) { return std::bit_width(unsigned(std::max(width, height))) - 1; }

Texture2D::Texture2D(TextureFormat format, int width, int height, std::vector<uint8_t> rgba8) : format_(format) {
  if (width < 1 || height < 1)
    throw std::invalid_argument("texture size " + std::to_string(width) + "x" + std::to_string(height) + ": must be at least 1x1");
  if (rgba8.size() != size_t(width) * size_t(height) * 4)
    throw std::invalid_argument("texture of " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                                std::to_string(size_t(width) * size_t(height) * 4) + " bytes, got " +
                                std::to_string(rgba8.size()));
  levels_.push_back(TextureLevel{width, height, std::move(rgba8)});
}

glm::dvec4 Texture2D::texel(int level, int i, int j) const {
  const TextureLevel& l = levels_[size_t(level)];
  const uint8_t* p = &l.texels[(size_t(j) * size_t(l.width) + size_t(i)) * 4];
  glm::dvec4 c;
  for (int k = 0; k < 4; ++k) c[k] = decodeChannel(format_, p[k], k);
  return c;
}

TextureLevel generateMipmapLevel(TextureFormat format, const TextureLevel& source) {
  TextureLevel out;
  out.width = std::max(1, source.width / 2);
  out.height = std::max(1, source.height / 2);
  out.texels.resize(size_t(out.width) * size_t(out.height) * 4);
  const bool srgb = format == TextureFormat::Srgb8Alpha8;
  auto read = [&](int i, int j, int k) {
    return decodeChannel(format, source.texels[(size_t(j) * size_t(source.width) + size_t(i)) * 4 + size_t(k)], k);
  };
  for (int j = 0; j < out.height; ++j)
    for (int i = 0; i < out.width; ++i) {
      const int i0 = std::min(2 * i, source.width - 1), i1 = std::min(2 * i + 1, source.width - 1);
      const int j0 = std::min(2 * j, source.height - 1), j1 = std::min(2 * j + 1, source.height - 1);
      for (int k = 0; k < 4; ++k) {
        double mean = 0.25 * (read(i0, j0, k) + read(i1, j0, k) + read(i0, j1, k) + read(i1, j1, k));
        if (srgb && k < 3) mean = linearToSrgb(mean);
        // Round to nearest (§2.3.5.2's conversion of a float to UNORM), ties to even.
        out.texels[(size_t(j) * size_t(out.width) + size_t(i)) * 4 + size_t(k)] =
            uint8_t(std::nearbyint(std::clamp(mean, 0.0, 1.0) * 255.0));
      }
    }
  return out;
}

void Texture2D::generateMipmaps() {
  levels_.resize(1);
  const int q = lastMipmapLevel(levels_[0].width, levels_[0].height);
  for (int i = 1; i <= q; ++i) levels_.push_back(generateMipmapLevel(format_, levels_.back()));
}

void Texture2D::setLevel(int i, TextureLevel level) {
  if (i < 1 || i > levels())
    throw std::invalid_argument("texture level " + std::to_string(i) + ": levels 1.." + std::to_string(levels()) + " can be set");
  const int w = std::max(1, levels_[0].width >> i), h = std::max(1, levels_[0].height >> i);
  if (level.width != w || level.height != h || level.texels.size() != size_t(w) * size_t(h) * 4)
    throw std::invalid_argument("texture level " + std::to_string(i) + " must be " + std::to_string(w) + "x" +
                                std::to_string(h) + " with " + std::to_string(size_t(w) * size_t(h) * 4) + " bytes");
  if (i == levels()) levels_.push_back(std::move(level));
  else levels_[size_t(i)] = std::move(level);
}

double lodFromDerivatives(double dsdx, double dtdx, double dsdy, double dtdy, int width, int height) {
  const double dudx = dsdx * width, dvdx = dtdx * height, dudy = dsdy * width, dvdy = dtdy * height;
  const double rho = std::max(std::sqrt(dudx * dudx + dvdx * dvdx), std::sqrt(dudy * dudy + dvdy * dvdy));
  return std::log2(rho);
}

float llvmpipeLod(float dsdx, float dtdx, float dsdy, float dtdy, int width, int height) {
  const float w = float(width), h = float(height);
  const float sx = dsdx * w, sy = dsdy * w, tx = dtdx * h, ty = dtdy * h;
  const float rhoX = sx * sx + tx * tx, rhoY = sy * sy + ty * ty;
  const float rho = rhoX > rhoY ? rhoX : rhoY;
  const uint32_t bits = std::bit_cast<uint32_t>(rho);
  const float exponent = float(int32_t((bits >> 23) & 255u) - 128);  // lp_build_extract_exponent(x, −1)
  const float mantissa = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);
  return (exponent + mantissa) * 0.5f;
}

}  // namespace oitref
