// Unsorted OVER: transparent objects blended over the opaque background in submission order
// (object order, then triangle order) — what a renderer does without OIT. Order-dependent.
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

class Over final : public Method {
 public:
  const MethodInfo& info() const override { return overInfo(); }
  std::vector<AttachmentDecl> attachments() const override { return opaqueAttachments(); }
  FrameResult render(const FrameContext& context) override {
    FrameResult result;
    FrameTargets targets(attachments(), context);
    PassRunner run(context, result);
    run.opaquePass(targets);
    Framebuffer fb = targets.present(true);
    const PipelineState st = transparentState(context.profile, overBlend());
    run.transparentPass("transparent", fb, st, [](const FragmentInput&, const glm::vec4& c, FragmentOutput& out) {
      out.write(0, c);
      out.write(1, c);
    });
    targets.finish(result, "opaque");
    return result;
  }
};

}  // namespace

const MethodInfo& overInfo() {
  static const MethodInfo info{"over", "unsorted OVER in submission order (object, then triangle order)", {}};
  return info;
}
std::unique_ptr<Method> makeOver(const MethodOptions&) { return std::make_unique<Over>(); }

}  // namespace oitref::methods
