// Scene JSON → Scene, with errors that name the file and the field. Format: oitref/oit/scene.h.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "oitref/core/image.h"
#include "oitref/oit/scene.h"
#include "oitref/oit/scene_geometry.h"
#include "scene/colour_rule.h"
#include "scene/texture_file.h"
#include "util/did_you_mean.h"

namespace oitref {
namespace {

using json = nlohmann::json;

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw SceneError(path_ + ": " + (field.empty() ? "" : field + ": ") + what);
  }

  void onlyKeys(const json& object, const std::string& field, const std::vector<std::string>& allowed) const {
    for (const auto& [key, value] : object.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      fail(field.empty() ? key : field + "." + key, "unknown key" + util::didYouMean(key, allowed));
    }
  }

  float number(const json& v, const std::string& field) const {
    if (!v.is_number()) fail(field, "expected a number, got " + std::string(v.type_name()));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(field, "expected a finite number");
    // Every scene number becomes an fp32: one beyond its range (it would be infinite) or so small
    // that it would be 0 is refused, not changed.
    const float f = float(d);
    if (!std::isfinite(f) || (f == 0.0f && d != 0.0))
      fail(field, v.dump() + " does not fit in fp32 (" + (std::isfinite(f) ? "it would be 0" : "largest 3.40282347e38") + ")");
    return f;
  }

  template <int N>
  glm::vec<N, float> vector(const json& v, const std::string& field) const {
    if (!v.is_array() || v.size() != N)
      fail(field, "expected an array of " + std::to_string(N) + " numbers");
    glm::vec<N, float> out;
    for (int i = 0; i < N; ++i) out[i] = number(v[size_t(i)], field + "[" + std::to_string(i) + "]");
    return out;
  }

  int integer(const json& v, const std::string& field, long lo, long hi) const {
    if (!v.is_number_integer()) fail(field, "expected an integer, got " + std::string(v.type_name()));
    const long x = v.get<long>();
    if (x < lo || x > hi) fail(field, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(x));
    return int(x);
  }

  glm::vec4 color(const json& v, const std::string& field) const {
    const glm::vec4 c = vector<4>(v, field);
    int channel = 0;
    if (const char* problem = detail::colourProblem(c, channel)) fail(field + "[" + std::to_string(channel) + "]", problem);
    return c;
  }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

Camera readCamera(const Reader& r, const json& j) {
  const std::string f = "camera";
  if (!j.is_object()) r.fail(f, "expected an object");
  r.onlyKeys(j, f, {"position", "target", "up", "fov_y", "near", "far"});
  Camera c;
  if (j.contains("position")) c.position = r.vector<3>(j["position"], f + ".position");
  if (j.contains("target")) c.target = r.vector<3>(j["target"], f + ".target");
  if (j.contains("up")) c.up = r.vector<3>(j["up"], f + ".up");
  if (j.contains("fov_y")) c.fovYDegrees = r.number(j["fov_y"], f + ".fov_y");
  if (j.contains("near")) c.nearPlane = r.number(j["near"], f + ".near");
  if (j.contains("far")) c.farPlane = r.number(j["far"], f + ".far");
  if (!(c.fovYDegrees > 0.0f && c.fovYDegrees < 180.0f)) r.fail(f + ".fov_y", "must lie in (0, 180) degrees");
  if (!(c.nearPlane > 0.0f)) r.fail(f + ".near", "must be positive");
  if (!(c.farPlane > c.nearPlane)) r.fail(f + ".far", "must be greater than near");
  const glm::vec3 forward = c.target - c.position;
  if (glm::dot(forward, forward) == 0.0f) r.fail(f + ".target", "must differ from the position");
  if (glm::dot(c.up, c.up) == 0.0f) r.fail(f + ".up", "must not be zero");
  const glm::vec3 side = glm::cross(forward, c.up);
  if (glm::dot(side, side) <= 1e-12f * glm::dot(forward, forward) * glm::dot(c.up, c.up))
    r.fail(f + ".up", "must not be parallel to the view direction");
  // Last: the projection's check undoes the view too, which the rules above make invertible.
  if (const std::string problem = c.projectionProblem(1.0f); !problem.empty()) r.fail(f, problem);
  return c;
}

SamplerState readSampler(const Reader& r, const json& j, const std::string& f) {
  if (!j.is_object()) r.fail(f, "expected an object");
  r.onlyKeys(j, f, {"min_filter", "mag_filter", "wrap_s", "wrap_t", "lod_bias"});
  SamplerState s;
  auto text = [&](const char* key) {
    if (!j[key].is_string()) r.fail(f + "." + key, "expected a string");
    return j[key].get<std::string>();
  };
  try {
    if (j.contains("min_filter")) s.minFilter = parseTextureFilter(text("min_filter"));
    if (j.contains("mag_filter")) {
      s.magFilter = parseTextureFilter(text("mag_filter"));
      if (s.magFilter != TextureFilter::Nearest && s.magFilter != TextureFilter::Linear)
        r.fail(f + ".mag_filter", "must be nearest or linear (GL 4.6 §8.15)");
    }
    if (j.contains("wrap_s")) s.wrapS = parseWrapMode(text("wrap_s"));
    if (j.contains("wrap_t")) s.wrapT = parseWrapMode(text("wrap_t"));
  } catch (const std::invalid_argument& e) {
    r.fail(f, e.what());
  }
  if (j.contains("lod_bias")) s.lodBias = r.number(j["lod_bias"], f + ".lod_bias");
  return s;
}

// "texture", "texture_format", "sampler" and "alpha_test" of either object type.
void readTexturing(const Reader& r, const json& j, const std::string& f, const std::filesystem::path& folder,
                   SceneObject& o) {
  if (j.contains("texture")) {
    if (!j["texture"].is_string() || j["texture"].get<std::string>().empty()) r.fail(f + ".texture", "expected a path string");
    o.textureFile = (folder / j["texture"].get<std::string>()).lexically_normal().string();
  }
  if (j.contains("texture_format")) {
    const json& v = j["texture_format"];
    const std::string name = v.is_string() ? v.get<std::string>() : "";
    if (name == "rgba8") o.textureFormat = TextureFormat::Rgba8;
    else if (name == "srgb8_alpha8") o.textureFormat = TextureFormat::Srgb8Alpha8;
    else r.fail(f + ".texture_format", "expected \"rgba8\" or \"srgb8_alpha8\"");
  }
  if (j.contains("sampler")) o.sampler = readSampler(r, j["sampler"], f + ".sampler");
  if (j.contains("alpha_test")) {
    const float t = r.number(j["alpha_test"], f + ".alpha_test");
    if (!(t >= 0.0f && t <= 1.0f)) r.fail(f + ".alpha_test", "must lie in [0, 1]");
    o.alphaTest = t;
  }
}

SceneObject readObject(const Reader& r, const json& j, const std::string& f, const std::filesystem::path& folder) {
  if (!j.is_object()) r.fail(f, "expected an object");
  if (!j.contains("type") || !j["type"].is_string()) r.fail(f + ".type", "expected \"mesh\" or \"particle\"");
  const std::string type = j["type"].get<std::string>();
  SceneObject o;
  if (type == "mesh") {
    o.type = ObjectType::Mesh;
    r.onlyKeys(j, f, {"type", "file_path", "color_override", "position", "rotation", "scale", "transparent", "texture",
                      "texture_format", "sampler", "alpha_test"});
    if (!j.contains("file_path") || !j["file_path"].is_string()) r.fail(f + ".file_path", "expected a path string");
    o.filePath = (folder / j["file_path"].get<std::string>()).lexically_normal().string();
  } else if (type == "particle") {
    o.type = ObjectType::Particles;
    r.onlyKeys(j, f, {"type", "count", "seed", "color_override", "position", "rotation", "scale", "size", "transparent",
                      "texture", "texture_format", "sampler", "alpha_test"});
    if (!j.contains("count")) r.fail(f + ".count", "missing: the number of particles");
    o.particleCount = r.integer(j["count"], f + ".count", 0, 1'000'000);
    if (j.contains("seed")) o.seed = uint32_t(r.integer(j["seed"], f + ".seed", 0, 0xffffffffL));
    if (j.contains("size")) o.particleSize = r.number(j["size"], f + ".size");
    if (!(o.particleSize > 0.0f)) r.fail(f + ".size", "must be positive");
  } else {
    r.fail(f + ".type", "unknown object type '" + type + "' (valid: mesh, particle)");
  }
  readTexturing(r, j, f, folder, o);
  if (j.contains("color_override")) o.colorOverride = r.color(j["color_override"], f + ".color_override");
  if (j.contains("position")) o.position = r.vector<3>(j["position"], f + ".position");
  if (j.contains("rotation")) o.rotationDegrees = r.vector<3>(j["rotation"], f + ".rotation");
  if (j.contains("scale")) o.scale = r.number(j["scale"], f + ".scale");
  if (!(o.scale > 0.0f)) r.fail(f + ".scale", "must be positive");
  if (j.contains("transparent")) {
    if (!j["transparent"].is_boolean()) r.fail(f + ".transparent", "expected true or false");
    o.transparentOverride = j["transparent"].get<bool>();
  }
  return o;
}

}  // namespace

Scene parseScene(const std::string& jsonText, const std::string& path) {
  const Reader r(path);
  json j;
  try {
    j = json::parse(jsonText, nullptr, true, /*ignore_comments=*/true);
  } catch (const json::exception& e) {  // parse errors, and numbers beyond double (out_of_range 406)
    r.fail("", std::string("malformed JSON: ") + e.what());
  }
  if (!j.is_object()) r.fail("", "expected a JSON object at the top level");
  r.onlyKeys(j, "", {"back", "resolution", "camera", "objects"});
  Scene s;
  s.sourcePath = path;
  if (j.contains("back")) {
    s.background = r.vector<3>(j["back"], "back");
    for (int i = 0; i < 3; ++i)
      if (s.background[i] < 0.0f) r.fail("back[" + std::to_string(i) + "]", "colour components must not be negative");
  }
  if (j.contains("resolution")) {
    const json& res = j["resolution"];
    if (!res.is_array() || res.size() != 2) r.fail("resolution", "expected [width, height]");
    s.width = r.integer(res[0], "resolution[0]", 1, Image::kMaxDimension);
    s.height = r.integer(res[1], "resolution[1]", 1, Image::kMaxDimension);
  }
  if (j.contains("camera")) s.camera = readCamera(r, j["camera"]);
  if (!j.contains("objects") || !j["objects"].is_array()) r.fail("objects", "expected an array of objects");
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  for (size_t i = 0; i < j["objects"].size(); ++i)
    s.objects.push_back(readObject(r, j["objects"][i], "objects[" + std::to_string(i) + "]", folder));
  return s;
}

Scene loadScene(const std::string& path, uint64_t memoryLimit) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw SceneError(path + ": is a folder, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return loadSceneText(text.str(), path, memoryLimit);
}

Scene loadSceneText(const std::string& jsonText, const std::string& path, uint64_t memoryLimit) {
  Scene s = parseScene(jsonText, path);
  // Each file is imported once, however many objects use it (a scene of 250 quads is one import).
  std::map<std::string, TriangleMesh> loaded;
  std::map<std::pair<std::string, TextureFormat>, std::shared_ptr<const Texture2D>> textures;  // likewise
  for (size_t i = 0; i < s.objects.size(); ++i) {
    SceneObject& o = s.objects[i];
    const std::string field = path + ": objects[" + std::to_string(i) + "]";
    if (o.type == ObjectType::Mesh) {
      auto it = loaded.find(o.filePath);
      if (it == loaded.end()) {
        try {
          it = loaded.emplace(o.filePath, loadMesh(o.filePath, 120.0, memoryLimit)).first;
        } catch (const SceneError& e) {
          throw SceneError(field + ".file_path: " + e.what());
        }
      }
      o.mesh = it->second;
    }
    // The object's "texture", else its model's material's.
    const bool fromMaterial = o.textureFile.empty() && !o.mesh.texturePath.empty();
    if (fromMaterial) o.textureFile = o.mesh.texturePath;
    if (o.textureFile.empty()) {
      if (o.alphaTest) throw SceneError(field + ".alpha_test: the object has no texture (\"texture\", or a material's)");
      continue;
    }
    if (o.type == ObjectType::Mesh && o.mesh.texcoords.size() != o.mesh.positions.size())
      throw SceneError(field + ".texture: the model '" + o.filePath + "' has no texture coordinates (in every mesh)");
    auto t = textures.find({o.textureFile, o.textureFormat});
    if (t == textures.end()) {
      try {
        t = textures.emplace(std::pair{o.textureFile, o.textureFormat}, detail::loadTextureFile(o.textureFile, o.textureFormat, memoryLimit)).first;
      } catch (const SceneError& e) {
        throw SceneError(field + (fromMaterial ? ".file_path: the model '" + o.filePath + "' names a texture: " : ".texture: ") +
                         e.what());
      }
    }
    o.texture = t->second;
  }
  // Both ground truths draw this geometry; where fp32 depth cannot hold it the rasterizer would
  // lose what the ray cast sees (depth_precision.cpp).
  if (const std::string problem = depthPrecisionProblem(buildSceneGeometry(s)); !problem.empty())
    throw SceneError(path + ": camera: " + problem);
  return s;
}

}  // namespace oitref
