// Each method's description and factory; one source file per method.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "oitref/method.h"
#include "oitref/pipeline_state.h"

namespace oitref::methods {


const MethodInfo& opaqueInfo();
std::unique_ptr<Method> makeOpaque(const MethodOptions& options);
const MethodInfo& overInfo();
std::unique_ptr<Method> makeOver(const MethodOptions& options);
// over's transparent draws for its `faces` option, in order: each pass's name and the faces it
// culls (the C++ method and its GL version in glcheck both draw these).
std::vector<std::pair<std::string, CullMode>> overDraws(const std::string& faces);
const MethodInfo& sortedInfo();
std::unique_ptr<Method> makeSorted(const MethodOptions& options);
const MethodInfo& wsumInfo();
std::unique_ptr<Method> makeWsum(const MethodOptions& options);
const MethodInfo& wavgInfo();
std::unique_ptr<Method> makeWavg(const MethodOptions& options);
const MethodInfo& wboitInfo();
std::unique_ptr<Method> makeWboit(const MethodOptions& options);
const MethodInfo& mboitInfo();
std::unique_ptr<Method> makeMboit(const MethodOptions& options);
const MethodInfo& mtInfo();
std::unique_ptr<Method> makeMt(const MethodOptions& options);
const MethodInfo& meshkin3Info();
std::unique_ptr<Method> makeMeshkin3(const MethodOptions& options);
const MethodInfo& mlabInfo();
std::unique_ptr<Method> makeMlab(const MethodOptions& options);
const MethodInfo& kbufferInfo();
std::unique_ptr<Method> makeKbuffer(const MethodOptions& options);
const MethodInfo& dfaoitInfo();
std::unique_ptr<Method> makeDfaoit(const MethodOptions& options);
const MethodInfo& stochasticInfo();
std::unique_ptr<Method> makeStochastic(const MethodOptions& options);
std::unique_ptr<Method> makeStochasticVallius(const MethodOptions& options);  // variant=vallius (stochastic_vallius.cpp)
// The key of a fragment's random numbers (stochastic.cpp; the variants hash it with SplitMix64).
uint64_t stochasticFragmentKey(uint32_t seed, int x, int y, uint32_t object, uint32_t primitive);
// The coverage mask of one fragment: round(α·samples) of the low `samples` bits (stochastic.cpp).
uint32_t stochasticMask(uint32_t seed, int x, int y, uint32_t object, uint32_t primitive, float alpha, int samples);
const MethodInfo& dualpeelInfo();
std::unique_ptr<Method> makeDualpeel(const MethodOptions& options);
const MethodInfo& hybridInfo();
std::unique_ptr<Method> makeHybrid(const MethodOptions& options);
const MethodInfo& screendoorInfo();
std::unique_ptr<Method> makeScreendoor(const MethodOptions& options);
// The N×N Bayer matrix entry at (x mod N, y mod N), N a power of two (screendoor.cpp).
uint32_t bayerIndex(int n, int x, int y);
const MethodInfo& peelInfo();
std::unique_ptr<Method> makePeel(const MethodOptions& options);
const MethodInfo& raycastInfo();
std::unique_ptr<Method> makeRaycast(const MethodOptions& options);
const MethodInfo& abufferInfo();
std::unique_ptr<Method> makeAbuffer(const MethodOptions& options);

}  // namespace oitref::methods
