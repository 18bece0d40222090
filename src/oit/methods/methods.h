// Each method's description and factory; one source file per method.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "oitref/oit/method.h"
#include "oitref/core/pipeline_state.h"

namespace oitref::methods {

// Each built-in method's description and factory, defined in its own file.
#define OITREF_METHOD(name) \
  const MethodInfo& name##Info();  \
  std::unique_ptr<Method> name##Factory(const MethodOptions& options);
#include "methods/builtin_methods.def"
#undef OITREF_METHOD

// over's transparent draws for its `faces` option, in order: each pass's name and the faces it
// culls (the C++ method and its GL version in glcheck both draw these).
std::vector<std::pair<std::string, CullMode>> overDraws(const std::string& faces);
std::unique_ptr<Method> stochasticValliusFactory(const MethodOptions& options);  // variant=vallius (stochastic_vallius.cpp)
// The key of a fragment's random numbers (stochastic.cpp; the variants hash it with SplitMix64).
uint64_t stochasticFragmentKey(uint32_t seed, int x, int y, uint32_t object, uint32_t primitive);
// The coverage mask of one fragment: round(α·samples) of the low `samples` bits (stochastic.cpp).
uint32_t stochasticMask(uint32_t seed, int x, int y, uint32_t object, uint32_t primitive, float alpha, int samples);
// The N×N Bayer matrix entry at (x mod N, y mod N), N a power of two (screendoor.cpp).
uint32_t bayerIndex(int n, int x, int y);

}  // namespace oitref::methods
