// Blend-case CSV text → forEachBlendCsvCase and evaluate() under both profiles. Bad lines must be
// reported, never crash.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "tools/blend_case.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::ostringstream err;
  const oitref::Profile exact = oitref::exactProfile(), llvmpipe = oitref::parseProfile("llvmpipe");
  oitref::tools::forEachBlendCsvCase(in, err, "fuzz.csv", [&](int, const std::string&, const oitref::tools::BlendCase& c) {
    (void)oitref::tools::evaluate(c, exact);
    (void)oitref::tools::evaluate(c, llvmpipe);
  });
  return 0;
}
