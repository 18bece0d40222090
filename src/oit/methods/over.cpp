// Unsorted OVER: transparent objects blended over the opaque background in submission order
// (object order, then triangle order) — what a renderer does without OIT. Order-dependent.
// `faces` (the OIT demo of google/bigwheels, source 003: "Split draw calls for back/front faces"):
// the transparent objects drawn once with both faces, or twice — every back face (front faces
// culled), then every front face (back faces culled) — so that a closed convex mesh blends its
// far side first; or one side only. Front faces wind counter-clockwise (GL's default).
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

class Over final : public OpaqueFirstMethod {
 public:
  explicit Over(const MethodOptions& o) : faces_(o.text("faces")) {}
  const MethodInfo& info() const override { return overInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& targets, FrameResult& /*result*/) override {
    Framebuffer fb = targets.present(true);
    for (const auto& [name, cull] : overDraws(faces_)) {
      PipelineState st = transparentState(context.profile, overBlend());
      st.raster.cull = cull;
      run.transparentPass(name, fb, st, [](const FragmentInput&, const glm::vec4& c, FragmentOutput& out) {
        out.write(0, c);
        out.write(1, c);
      });
    }
  }

 private:
  std::string faces_;
};

}  // namespace

std::vector<std::pair<std::string, CullMode>> overDraws(const std::string& faces) {
  if (faces == "split") return {{"back faces", CullMode::Front}, {"front faces", CullMode::Back}};
  if (faces == "back") return {{"back faces", CullMode::Front}};
  if (faces == "front") return {{"front faces", CullMode::Back}};
  return {{"transparent", CullMode::None}};
}

const MethodInfo& overInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{
      "over",
      "unsorted OVER in submission order (object, then triangle order)",
      {{"faces", "all",
        "all: one draw with both faces; split: every back face, then every front face (two culled draws, as the "
        "bigwheels OIT demo); back, front: that side only",
        {"all", "split", "back", "front"}}}};
    i.studyVariants = {{{"faces", "split"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> overFactory(const MethodOptions& o) { return std::make_unique<Over>(o); }

}  // namespace oitref::methods
