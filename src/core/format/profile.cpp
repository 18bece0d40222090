#include "oitref/core/profile.h"

#include <sstream>
#include <stdexcept>

namespace oitref {
namespace {

const char* roundingName(Rounding r) { return r == Rounding::NearestEven ? "rne" : "rtz"; }
const char* unormName(UnormRounding u) {
  return u == UnormRounding::ExactNearestEven ? "exact" : u == UnormRounding::Fp32Product ? "fp32" : "nvidia";
}
const char* unormBlendName(UnormBlend b) { return b == UnormBlend::Float ? "float" : b == UnormBlend::Integer ? "integer" : "nvidia"; }
const char* textureFilteringName(TextureFiltering t) {
  return t == TextureFiltering::Exact ? "exact" : t == TextureFiltering::Llvmpipe ? "llvmpipe" : "nvidia";
}
const char* floatBlendName(FloatBlend b) { return b == FloatBlend::Ieee ? "ieee" : b == FloatBlend::Llvmpipe ? "llvmpipe" : "nvidia"; }

Rounding parseRounding(const std::string& key, const std::string& v) {
  if (v == "rne") return Rounding::NearestEven;
  if (v == "rtz") return Rounding::TowardZero;
  throw std::invalid_argument("profile key '" + key + "': expected rne or rtz, got '" + v + "'");
}

}  // namespace

std::string Profile::describe() const {
  std::ostringstream s;
  s << name << " (fp16=" << roundingName(fp16) << ", packed=" << roundingName(packedFloat)
    << ", minifloat=" << roundingName(minifloat)
    << ", unorm=" << unormName(unorm) << ", unorm_blend=" << unormBlendName(unormBlend)
    << ", float_blend=" << floatBlendName(floatBlend) << ", fma=" << (fma ? "on" : "off")
    << ", texture=" << textureFilteringName(texture)
    << ", raster=" << (raster == Rasterization::Exact ? "exact" : raster == Rasterization::Llvmpipe ? "llvmpipe" : "nvidia")
    << ", math=" << (math == ShaderMath::Exact ? "exact" : "llvmpipe")
    << ", fill=" << (fill == FillRule::State ? "state" : "bottom_left") << ")";
  return s.str();
}

Profile exactProfile() { return Profile{}; }

Profile llvmpipeProfile() {
  Profile p;
  p.name = "llvmpipe";
  p.fp16 = Rounding::TowardZero;
  p.packedFloat = Rounding::TowardZero;
  p.minifloat = Rounding::NearestEven;
  p.unorm = UnormRounding::Fp32Product;
  p.unormBlend = UnormBlend::Integer;
  p.floatBlend = FloatBlend::Llvmpipe;
  p.fma = true;
  p.texture = TextureFiltering::Llvmpipe;
  p.raster = Rasterization::Llvmpipe;
  p.math = ShaderMath::Llvmpipe;
  p.fill = FillRule::BottomLeft;
  return p;
}

Profile nvidiaProfile() {
  Profile p;
  p.name = "nvidia";
  p.fp16 = Rounding::TowardZero;
  p.packedFloat = Rounding::TowardZero;
  p.minifloat = Rounding::NearestEven;  // no GPU format: user minifloats keep the exact rules
  p.unorm = UnormRounding::NvidiaFixed;
  p.unormBlend = UnormBlend::Nvidia;
  p.floatBlend = FloatBlend::Nvidia;
  p.fma = false;
  p.texture = TextureFiltering::Nvidia;
  p.raster = Rasterization::Nvidia;
  p.fill = FillRule::BottomLeft;
  return p;
}

Profile parseProfile(const std::string& text) {
  std::istringstream in(text);
  std::string part;
  std::getline(in, part, ',');
  Profile p;
  if (part == "exact") p = exactProfile();
  else if (part == "llvmpipe") p = llvmpipeProfile();
  else if (part == "nvidia") p = nvidiaProfile();
  else throw std::invalid_argument("unknown profile '" + part + "' (valid: exact, llvmpipe, nvidia)");
  bool overridden = false;
  while (std::getline(in, part, ',')) {
    const auto eq = part.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument("profile override '" + part + "' is not key=value");
    const std::string key = part.substr(0, eq), value = part.substr(eq + 1);
    if (key == "fp16") p.fp16 = parseRounding(key, value);
    else if (key == "packed") p.packedFloat = parseRounding(key, value);
    else if (key == "minifloat") p.minifloat = parseRounding(key, value);
    else if (key == "unorm") {
      if (value == "exact") p.unorm = UnormRounding::ExactNearestEven;
      else if (value == "fp32") p.unorm = UnormRounding::Fp32Product;
      else if (value == "nvidia") p.unorm = UnormRounding::NvidiaFixed;
      else throw std::invalid_argument("profile key 'unorm': expected exact, fp32 or nvidia, got '" + value + "'");
    } else if (key == "unorm_blend") {
      if (value == "float") p.unormBlend = UnormBlend::Float;
      else if (value == "integer") p.unormBlend = UnormBlend::Integer;
      else if (value == "nvidia") p.unormBlend = UnormBlend::Nvidia;
      else throw std::invalid_argument("profile key 'unorm_blend': expected float, integer or nvidia, got '" + value + "'");
    } else if (key == "float_blend") {
      if (value == "ieee") p.floatBlend = FloatBlend::Ieee;
      else if (value == "llvmpipe") p.floatBlend = FloatBlend::Llvmpipe;
      else if (value == "nvidia") p.floatBlend = FloatBlend::Nvidia;
      else throw std::invalid_argument("profile key 'float_blend': expected ieee, llvmpipe or nvidia, got '" + value + "'");
    } else if (key == "texture") {
      if (value == "exact") p.texture = TextureFiltering::Exact;
      else if (value == "llvmpipe") p.texture = TextureFiltering::Llvmpipe;
      else if (value == "nvidia") p.texture = TextureFiltering::Nvidia;
      else throw std::invalid_argument("profile key 'texture': expected exact, llvmpipe or nvidia, got '" + value + "'");
    } else if (key == "raster") {
      if (value == "exact") p.raster = Rasterization::Exact;
      else if (value == "llvmpipe") p.raster = Rasterization::Llvmpipe;
      else if (value == "nvidia") p.raster = Rasterization::Nvidia;
      else throw std::invalid_argument("profile key 'raster': expected exact, llvmpipe or nvidia, got '" + value + "'");
    } else if (key == "math") {
      if (value == "exact") p.math = ShaderMath::Exact;
      else if (value == "llvmpipe") p.math = ShaderMath::Llvmpipe;
      else throw std::invalid_argument("profile key 'math': expected exact or llvmpipe, got '" + value + "'");
    } else if (key == "fill") {
      if (value == "state") p.fill = FillRule::State;
      else if (value == "bottom_left") p.fill = FillRule::BottomLeft;
      else throw std::invalid_argument("profile key 'fill': expected state or bottom_left, got '" + value + "'");
    } else if (key == "fma") {
      if (value == "on") p.fma = true;
      else if (value == "off") p.fma = false;
      else throw std::invalid_argument("profile key 'fma': expected on or off, got '" + value + "'");
    } else {
      throw std::invalid_argument("unknown profile key '" + key +
                                  "' (valid: fp16, packed, minifloat, unorm, unorm_blend, float_blend, fma, texture, raster, math, fill)");
    }
    overridden = true;
  }
  if (overridden) p.name = text;
  return p;
}

}  // namespace oitref
