// "Solid only" (Rožek's thesis): every object drawn opaque, alpha ignored. The baseline cost.
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

class Opaque final : public Method {
 public:
  const MethodInfo& info() const override { return opaqueInfo(); }
  std::vector<AttachmentDecl> attachments() const override { return AttachmentList().declared(); }
  FrameResult render(const FrameContext& context) override {
    FrameResult result;
    FrameTargets targets(attachments(), context);
    PassRunner(context, result).opaquePass(targets, /*everything=*/true);
    targets.finish(result, AttachmentList::kOpaque);
    return result;
  }
};

}  // namespace

const MethodInfo& opaqueInfo() {
  static const MethodInfo info{"opaque", "everything drawn opaque (the thesis's \"solid only\")", {}};
  return info;
}
std::unique_ptr<Method> opaqueFactory(const MethodOptions&) { return std::make_unique<Opaque>(); }

}  // namespace oitref::methods
