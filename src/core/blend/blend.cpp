// The public blend entry points; the rules are in blend_math.h (documented in oitref/core/blend.h).
#include "blend/blend_math.h"
#include "blend/target_blender.h"
#include "oitref/core/blend.h"
#include "oitref/core/fp_environment.h"

namespace oitref {

glm::vec4 blendFloat(const BlendState& state, const glm::vec4& source, const glm::vec4& destination,
                     const glm::vec4& constant, bool fixedPoint, bool targetHasAlpha) {
  const DefaultFloatingPoint fp;
  const glm::vec4 c = fixedPoint ? detail::clampUnit4(constant) : constant;
  return detail::store4(detail::blendValues(detail::compileBlend(state), detail::load4(source),
                                            detail::load4(destination), detail::load4(c), fixedPoint, targetHasAlpha));
}

void blendIntoTexel(const Format& format, const BlendState& state, const glm::vec4& constant,
                    const Profile& profile, const glm::vec4& source, uint8_t* texel) {
  const DefaultFloatingPoint fp;
  detail::TargetBlender(format, state, constant, profile).blend(source, texel);
}

}  // namespace oitref
