// Two-dimensional textures and their sampling as the GL 4.6 specification writes it (§8.14–8.17,
// §8.24): UNORM8 and sRGB8 RGBA textures with mipmaps, nearest and linear filtering, the six
// minification filters, and the repeat, clamp-to-edge and mirrored-repeat wrap modes. The
// `exact` reading (sampleTexture): every weight and sum in double, the filtered colour rounded to
// fp32 once. The rules, with their sections, are in docs/rules.md ("Texture sampling").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

namespace oitref {

enum class TextureFormat : uint8_t { Rgba8, Srgb8Alpha8 };  // GL_RGBA8, GL_SRGB8_ALPHA8
// How a lookup filters: `Exact` every weight and sum in double (GL 4.6 as written); `Llvmpipe`
// and `Nvidia` the devices' fixed-point filters of UNORM8 textures (8-bit weights; docs/nvidia.md,
// "Texture sampling"). A profile's `texture` rule.
enum class TextureFiltering : uint8_t { Exact, Llvmpipe, Nvidia };
enum class WrapMode : uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter : uint8_t {
  Nearest,
  Linear,
  NearestMipmapNearest,
  LinearMipmapNearest,
  NearestMipmapLinear,
  LinearMipmapLinear
};

// A sampler's state with GL's initial values (REPEAT, NEAREST_MIPMAP_LINEAR
// minification, LINEAR magnification, LOD range [−1000, 1000], bias 0).
struct SamplerState {
  WrapMode wrapS = WrapMode::Repeat, wrapT = WrapMode::Repeat;
  TextureFilter minFilter = TextureFilter::NearestMipmapLinear;
  TextureFilter magFilter = TextureFilter::Linear;  // Nearest or Linear only
  float minLod = -1000.0f, maxLod = 1000.0f, lodBias = 0.0f;
  bool operator==(const SamplerState&) const = default;
};

const char* toString(WrapMode m);
const char* toString(TextureFilter f);
WrapMode parseWrapMode(const std::string& name);       // "repeat", "clamp_to_edge", "mirrored_repeat"
TextureFilter parseTextureFilter(const std::string& name);  // "nearest", ..., "linear_mipmap_linear"

// One texel array per level, RGBA8 bytes row by row, row 0 at t = 0 (GL's first row).
struct TextureLevel {
  int width = 0, height = 0;
  std::vector<uint8_t> texels;  // width · height · 4
};

class Texture2D {
 public:
  // Level 0 from RGBA8 bytes (width · height · 4); throws std::invalid_argument on a size of 0
  // or a byte count that does not match.
  Texture2D(TextureFormat format, int width, int height, std::vector<uint8_t> rgba8);

  // Levels 1 … q (lastMipmapLevel), each max(1, ⌊size/2⌋) per dimension (§8.14.3), by the
  // box filter of generateMipmapLevel; replaces any levels there were.
  void generateMipmaps();
  // Level i (1 ≤ i ≤ levels()) given as GL's glTexImage2D for that level would: its size must be
  // max(1, ⌊w/2^i⌋) × max(1, ⌊h/2^i⌋), else std::invalid_argument; level i replaces the old one or
  // is appended after level i − 1.
  void setLevel(int i, TextureLevel level);

  TextureFormat format() const { return format_; }
  int levels() const { return int(levels_.size()); }
  const TextureLevel& level(int i) const { return levels_[size_t(i)]; }
  // Texel (i, j) of a level as the filter reads it (§8.24: sRGB decoded), in double.
  glm::dvec4 texel(int level, int i, int j) const;

 private:
  TextureFormat format_;
  std::vector<TextureLevel> levels_;
};

// q = ⌊log2 max(w, h)⌋, the last mipmap level of a w × h texture (§8.14.3).
int lastMipmapLevel(int width, int height);

// The next level down from `source` (glGenerateMipmap; GL asks for no particular filter and
// recommends a box): texel (i, j) averages source texels 2i, 2i + 1 × 2j, 2j + 1 (an index past
// a one-texel-wide edge reads the edge again), sRGB colours decoded to linear first and encoded
// again after (alpha is linear in both formats); each channel rounded to the nearest UNORM8 value.
TextureLevel generateMipmapLevel(TextureFormat format, const TextureLevel& source);

// The sRGB transfer function of §8.24 (decode) and its inverse, in double.
double srgbToLinear(double encoded);
double linearToSrgb(double linear);

// λ_base = log2 ρ, ρ = max(‖(∂u/∂x, ∂v/∂x)‖, ‖(∂u/∂y, ∂v/∂y)‖) in texels (§8.14.1, with
// u = s·w_t, v = t·h_t); what a 2×2 quad's differences give.
double lodFromDerivatives(double dsdx, double dtdx, double dsdy, double dtdy, int width, int height);
// llvmpipe's λ (Mesa 22.3.6 defaults: no rho approximation, no brilinear, one λ per quad;
// gallivm/lp_bld_sample.c, lp_build_rho and lp_build_lod_selector), all in fp32: the quad's
// differences (∂/∂x between its top-left and top-right pixel, ∂/∂y between its top-left and
// the one above it: lp_build_packed_ddx_ddy_twocoord) times the size, squared, summed per
// direction, the larger of the two, then lp_build_fast_log2 (exponent − 1 plus the mantissa in
// [1, 2)) times ½.
float llvmpipeLod(float dsdx, float dtdx, float dsdy, float dtdy, int width, int height);

// The filtered colour at (s, t) for the level-of-detail λ_base (before the sampler's bias and
// clamp, which this applies, §8.14.1): magnified when λ ≤ 0 (§8.14), else minified by the
// sampler's minification filter, over the texture's levels (level_base 0, q its last).
// `rule` chooses the filter's arithmetic (λ_base is taken as given under every rule).
// `explicitLod`: λ_base is the shader's own (textureLod), one per fragment, rather than the
// quad's derivatives' (llvmpipe then filters some samplers in floating point, docs/rules.md).
glm::vec4 sampleTexture(const Texture2D& texture, const SamplerState& sampler, float s, float t, double lodBase,
                        TextureFiltering rule = TextureFiltering::Exact, bool explicitLod = false);

}  // namespace oitref
