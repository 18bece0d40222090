// A method written outside oitref's tree with its method kit (oitref/oit/method_kit.h).
#pragma once

namespace custom {

// Registers "clamped_sum" beside oitref's own methods (oitref::registerMethod).
void registerClampedSum();

}  // namespace custom
