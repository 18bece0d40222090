// Ground truth by ray casting with Embree 3, independent of the rasterizer: one ray per pixel
// centre through the same camera; an intersection filter records every hit along the ray and
// rejects it so traversal goes on; hits outside the view depth range [near, far] are dropped;
// the nearest opaque hit ends the list; transparent hits in front of it are sorted by view
// depth (ties by object, then primitive) and composited back to front with OVER in double.
// Attributes come from Embree's barycentrics, colours from the same shading function as the
// rasterizer (oitref/oit/scene_geometry.h). Rays are traced on the renderer's workers, and Embree
// builds with as many threads, so --threads means what it says here too.
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>


#include "methods/method_common.h"
#include "methods/methods.h"
#include "oitref/core/fp_environment.h"
#include "util/round_to_float.h"

namespace oitref::methods {
namespace {

struct Hit {
  unsigned part, primitive;
  float u, v;
  double viewDepth;
};

struct HitCollector {
  RTCIntersectContext context;  // first: Embree passes a pointer to it to the filter
  std::vector<Hit>* hits;
};

void collectHit(const RTCFilterFunctionNArguments* args) {
  auto* collector = reinterpret_cast<HitCollector*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    collector->hits->push_back({RTCHitN_geomID(args->hit, args->N, i), RTCHitN_primID(args->hit, args->N, i),
                                RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i),
                                double(RTCRayN_tfar(args->ray, args->N, i))});
    args->valid[i] = 0;  // reject, so the ray goes on to the next hit
  }
}

class EmbreeScene {
 public:
  // `threads`: Embree's own workers for the BVH build, the renderer's count.
  EmbreeScene(const SceneGeometry& geometry, int threads) {
    device_ = rtcNewDevice(("threads=" + std::to_string(threads)).c_str());
    if (!device_) throw std::runtime_error("raycast: Embree device creation failed (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    scene_ = rtcNewScene(device_);
    for (size_t p = 0; p < geometry.parts.size(); ++p) {
      const ScenePart& part = geometry.parts[p];
      RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                   3 * sizeof(float), std::max<size_t>(1, part.positions.size())));
      for (size_t v = 0; v < part.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) {
          if (!(std::fabs(part.positions[v][k]) <= kRayCastLargestCoordinate))
            throw std::runtime_error("raycast: object " + std::to_string(part.objectIndex) + " has a vertex at " +
                                     std::to_string(part.positions[v][k]) + " in world space, beyond Embree's range of ±1.844e18");
          vertices[3 * v + size_t(k)] = part.positions[v][k];
        }
      auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                     3 * sizeof(unsigned), part.triangleCount()));
      std::copy(part.indices.begin(), part.indices.end(), indices);
      rtcSetGeometryIntersectFilterFunction(g, collectHit);
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(scene_, g, unsigned(p));
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(scene_);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Every hit along the ray, t in units of the (unnormalised) direction.
  void allHits(glm::vec3 origin, glm::vec3 direction, std::vector<Hit>& hits) const {
    hits.clear();
    HitCollector collector;
    rtcInitIntersectContext(&collector.context);
    collector.hits = &hits;
    RTCRayHit rh{};
    rh.ray.org_x = origin.x, rh.ray.org_y = origin.y, rh.ray.org_z = origin.z;
    rh.ray.dir_x = direction.x, rh.ray.dir_y = direction.y, rh.ray.dir_z = direction.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &collector.context, &rh);
    // A primitive may be reported more than once (spatial splits): keep one.
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
      return std::tie(a.part, a.primitive) < std::tie(b.part, b.primitive);
    });
    hits.erase(std::unique(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
                 return a.part == b.part && a.primitive == b.primitive;
               }), hits.end());
    // A ray through an edge or vertex shared by triangles of one part hits each of them at the
    // same distance; the rasterizer's tie rule (top-left) gives such a pixel to exactly one of
    // them, so the surface is counted once here too: hits of one part whose distances agree to
    // 1e-6 relative are one hit, the lowest primitive kept.
    std::stable_sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
      return std::tie(a.part, a.viewDepth) < std::tie(b.part, b.viewDepth);
    });
    hits.erase(std::unique(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
                 return a.part == b.part && std::fabs(a.viewDepth - b.viewDepth) <= 1e-6 * std::fabs(a.viewDepth);
               }), hits.end());
  }

 private:
  RTCDevice device_;
  RTCScene scene_;
};

// The line through a pixel centre: from the camera along the pixel's line from the near plane
// (NDC z = −1) to the far plane (z = 1); when far/near is so large that the far plane's point is
// at infinity in the fp32 projection (w = 0: an infinite direction), to NDC z = 0 (view depth
// 2·near·far / (near + far)) instead.
struct PixelRays {
  glm::dmat4 inverse;
  glm::dvec3 origin;
  int width, height;
  glm::dvec3 direction(int x, int y) const {
    const glm::dvec2 ndc(2.0 * (x + 0.5) / width - 1.0, 2.0 * (y + 0.5) / height - 1.0);
    const glm::dvec4 a = inverse * glm::dvec4(ndc, -1.0, 1.0), b = inverse * glm::dvec4(ndc, 1.0, 1.0);
    glm::dvec3 d = glm::dvec3(b) / b.w - glm::dvec3(a) / a.w;
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) {
      const glm::dvec4 m = inverse * glm::dvec4(ndc, 0.0, 1.0);
      d = glm::dvec3(m) / m.w - glm::dvec3(a) / a.w;
    }
    // Only the line matters, not its length. A near plane of 1e-40 makes the direction ~1e-41:
    // denormal once in fp32, and Embree's hits NaN (fuzz_camera). One far outside [2^−30, 2^30]
    // is scaled by a power of two, which moves none of its bits relative to each other; ordinary
    // directions are left exactly as they were.
    const double largest = std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
    if (largest > 0.0 && std::isfinite(largest) && (largest < 0x1p-30 || largest > 0x1p30)) {
      int exponent = 0;
      std::frexp(largest, &exponent);
      d = {std::ldexp(d.x, -exponent), std::ldexp(d.y, -exponent), std::ldexp(d.z, -exponent)};
    }
    return d;
  }
};

// Attribute k of a part's triangle at barycentrics w (of its vertices 0, 1, 2), rounded to fp32.
float attributeAt(const ScenePart& part, unsigned primitive, const double w[3], int k) {
  double a = 0;
  for (int i = 0; i < 3; ++i) a += w[i] * double(part.attributes[part.indices[3 * primitive + size_t(i)] * kSceneAttributeCount + size_t(k)]);
  return util::roundToFloat(a);
}

// The texture coordinates' derivatives at pixel (x, y) on the hit's triangle, by the
// rasterizer's rule (FragmentStage::quadDerivatives): the coordinates where the lines through
// the pixel centres of its 2×2 quad meet the triangle's plane (inside the triangle or not), in
// fp32, differenced in double; ∂s/∂x, ∂t/∂x, ∂s/∂y, ∂t/∂y.
void texcoordDerivatives(const ScenePart& part, unsigned primitive, const PixelRays& rays, int x, int y, double out[4]) {
  glm::dvec3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = glm::dvec3(part.positions[part.indices[3 * primitive + size_t(i)]]);
  const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  auto at = [&](int px, int py, float st[2]) {  // Möller–Trumbore without the inside test
    const glm::dvec3 d = rays.direction(px, py);
    const glm::dvec3 q = glm::cross(d, e2);
    const double det = glm::dot(e1, q);
    const glm::dvec3 s = rays.origin - p[0];
    const double u = glm::dot(s, q) / det, v = glm::dot(d, glm::cross(s, e1)) / det;
    const double w[3] = {1.0 - u - v, u, v};
    st[0] = attributeAt(part, primitive, w, 4), st[1] = attributeAt(part, primitive, w, 5);
  };
  const int x0 = x & ~1, y0 = y & ~1;
  float left[2], right[2], bottom[2], top[2];
  at(x0, y, left), at(x0 + 1, y, right), at(x, y0, bottom), at(x, y0 + 1, top);
  for (int c = 0; c < 2; ++c) out[c] = double(right[c]) - double(left[c]), out[2 + c] = double(top[c]) - double(bottom[c]);
}

// The hit's straight colour (shadeSurface), and whether its object's alpha test discards it.
glm::vec4 shadeHit(const FrameContext& c, const Hit& h, const PixelRays& rays, int x, int y, bool& discarded) {
  const ScenePart& part = c.geometry.parts[h.part];
  const SceneObject& object = c.scene.objects[part.objectIndex];
  float attributes[kSceneAttributeCount];
  const double w[3] = {1.0 - double(h.u) - double(h.v), double(h.u), double(h.v)};
  for (int k = 0; k < kSceneAttributeCount; ++k) attributes[k] = attributeAt(part, h.primitive, w, k);
  double derivatives[4];
  const bool textured = shadeSurfaceDerivatives(object) >= 0;
  if (textured) texcoordDerivatives(part, h.primitive, rays, x, y, derivatives);
  const glm::vec4 color = shadeSurface(object, attributes, 1, textured ? derivatives : nullptr, 1, c.profile.texture);
  discarded = surfaceDiscards(object, color);
  return color;
}

class Raycast final : public Method {
 public:
  const MethodInfo& info() const override { return raycastInfo(); }
  std::vector<AttachmentDecl> attachments() const override { return {}; }
  // Embree's BVH is not declared up front; 160 B per triangle covers its vertex and index copies
  // and a BVH4 with triangle4 leaves (an estimate, not a measurement of Embree's allocator).
  std::vector<MemoryItem> memoryNeed(int width, int height, const SceneGeometry& geometry) const override {
    std::vector<MemoryItem> items = Method::memoryNeed(width, height, geometry);
    items.push_back({"Embree scene (estimated 160 B/triangle)", uint64_t(geometry.triangleCount()) * 160});
    return items;
  }
  FrameResult render(const FrameContext& c) override {
    FrameResult result;
    const auto t0 = std::chrono::steady_clock::now();
    const EmbreeScene scene(c.geometry, c.renderer.threads());
    result.passes.push_back({"build BVH", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(), {}});

    const auto t1 = std::chrono::steady_clock::now();
    const Camera& cam = c.scene.camera;
    const glm::dmat4 view(cam.view());
    const PixelRays rays{glm::inverse(glm::dmat4(cam.projection(float(c.width) / float(c.height))) * view),
                         glm::dvec3(cam.position), c.width, c.height};
    const glm::dvec3 forward = glm::normalize(glm::dvec3(cam.target - cam.position));
    Image result8(makeFormat(FormatId::RGBA8), c.width, c.height), resultFloat(makeFormat(FormatId::RGBA32F), c.width, c.height);
    c.renderer.parallelFor(size_t(c.height), [&](size_t row) {
      const int y = int(row);
      const DefaultFloatingPoint fp;
      std::vector<Hit> hits;
      for (int x = 0; x < c.width; ++x) {
        const glm::dvec3 origin = rays.origin, direction = rays.direction(x, y);
        if (!std::isfinite(direction.x) || !std::isfinite(direction.y) || !std::isfinite(direction.z))
          throw std::runtime_error("raycast: the camera gives no finite ray through pixel (" + std::to_string(x) + ", " +
                                   std::to_string(y) + ")");
        for (int k = 0; k < 3; ++k)  // the camera's check refuses such positions; Embree asserts on them
          if (!(std::fabs(origin[k]) <= kRayCastLargestCoordinate))
            throw std::runtime_error("raycast: the camera lies beyond Embree's range of ±1.844e18");
        scene.allHits(glm::vec3(origin), glm::vec3(direction), hits);
        for (Hit& h : hits) h.viewDepth = double(h.viewDepth) * glm::dot(glm::dvec3(glm::vec3(direction)), forward);
        std::erase_if(hits, [&](const Hit& h) { return h.viewDepth < cam.nearPlane || h.viewDepth > cam.farPlane; });
        std::sort(hits.begin(), hits.end(), [](const Hit& p, const Hit& q) {
          return std::tie(p.viewDepth, p.part, p.primitive) < std::tie(q.viewDepth, q.part, q.primitive);
        });
        // The nearest opaque hit that its alpha test keeps ends the list; discarded hits are no
        // surface at all.
        glm::dvec3 color(c.scene.background);
        size_t end = hits.size();
        bool discarded = false;
        for (size_t i = 0; i < hits.size(); ++i) {
          if (c.geometry.parts[hits[i].part].transparent) continue;
          const glm::vec4 s = shadeHit(c, hits[i], rays, x, y, discarded);
          if (discarded) continue;
          color = glm::dvec3(glm::vec3(s));
          end = i;
          break;
        }
        for (size_t i = end; i-- > 0;) {
          if (!c.geometry.parts[hits[i].part].transparent) continue;  // an opaque hit discarded
          const glm::vec4 s = shadeHit(c, hits[i], rays, x, y, discarded);
          if (discarded) continue;
          color = glm::dvec3(glm::vec3(s)) * double(s.a) + color * (1.0 - double(s.a));
        }
        const glm::vec4 out(glm::vec3(color), 1.0f);
        resultFloat.store(x, y, out, c.profile);
        result8.store(x, y, out, c.profile);
      }
    });
    result.passes.push_back({"trace", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count(), {}});
    result.final8 = std::move(result8);
    result.finalFloat = std::move(resultFloat);
    return result;
  }
};

}  // namespace

const MethodInfo& raycastInfo() {
  static const MethodInfo info{"raycast", "Embree 3 ray casting: every hit per pixel centre, sorted, OVER in double", {}};
  return info;
}
std::unique_ptr<Method> raycastFactory(const MethodOptions&) { return std::make_unique<Raycast>(); }

}  // namespace oitref::methods
