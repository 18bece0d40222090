// OVER after sorting the transparent geometry back to front by the view depth of centroids:
// sort=object orders whole objects (the centroid of their vertices), sort=triangle orders every
// transparent triangle of the scene. Shows where sorting fails: intersecting and cyclically
// overlapping surfaces, and large objects whose centroid misrepresents their depth.
#include <algorithm>
#include <chrono>
#include <numeric>

#include "methods/method_common.h"
#include "methods/methods.h"
#include "methods/sorted_order.h"

namespace oitref::methods {
namespace {

class Sorted final : public OpaqueFirstMethod {
 public:
  explicit Sorted(const MethodOptions& o) : byTriangle_(o.is("sort", "triangle")) {}
  const MethodInfo& info() const override { return sortedInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& targets, FrameResult& result) override {
    const std::vector<SortedTriangle> order = sortedTriangleOrder(context, byTriangle_);

    // One draw of all sorted triangles; the primitive id leads back to the object's shading.
    ScenePart merged;
    std::vector<size_t> objectOf;
    for (const SortedTriangle& t : order) {
      const ScenePart& part = context.geometry.parts[t.part];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = part.indices[3 * t.index + size_t(k)];
        merged.indices.push_back(uint32_t(merged.positions.size()));
        merged.positions.push_back(part.positions[v]);
        merged.attributes.insert(merged.attributes.end(), part.attributes.begin() + std::ptrdiff_t(v * kSceneAttributeCount),
                                 part.attributes.begin() + std::ptrdiff_t((v + 1) * kSceneAttributeCount));
      }
      objectOf.push_back(part.objectIndex);
    }
    Framebuffer fb = targets.present(true);
    const PipelineState st = transparentState(context.profile, overBlend());
    const auto t0 = std::chrono::steady_clock::now();
    PassReport report{"sorted transparent", 0, {}};
    // The objects' shading, chosen per fragment by its triangle; the draw declares what any of
    // them needs (texture coordinates' derivatives, the alpha test's discard).
    FragmentProgram program{[&](const FragmentInput& in, FragmentOutput& out) {
      const SceneObject& o = context.scene.objects[objectOf[in.primitiveId]];
      const glm::vec4 c =
          shadeSurface(o, in.attributes, in.attributeStride, in.derivatives, in.derivativeStride, context.profile.texture);
      if (surfaceDiscards(o, c)) return out.discard();
      out.write(0, c);
      out.write(1, c);
    }};
    for (size_t object : objectOf) {
      const SceneObject& o = context.scene.objects[object];
      program.derivativesOf = std::max(program.derivativesOf, shadeSurfaceDerivatives(o));
      program.mayDiscard = program.mayDiscard || o.alphaTest.has_value();
    }
    if (!order.empty()) report.stats = context.renderer.draw(fb, st, toClipGeometry(merged, run.viewProjection()), program);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    result.passes.push_back(report);
    result.stats.sortedTriangles = order.size();
  }

 private:
  bool byTriangle_;
};

}  // namespace

const MethodInfo& sortedInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{"sorted",
                 "OVER after sorting transparent geometry back to front by centroid view depth",
                 {{"sort", "object", "what is sorted: whole objects or single triangles", {"object", "triangle"}}}};
    i.studyVariants = {{{"sort", "triangle"}}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> sortedFactory(const MethodOptions& o) { return std::make_unique<Sorted>(o); }

}  // namespace oitref::methods
