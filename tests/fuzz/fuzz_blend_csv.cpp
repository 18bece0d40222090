// Blend-case CSV text → forEachBlendCsvCase and evaluate() under both profiles. Bad lines must be
// reported, never crash; a header without one of the input columns is refused with
// std::invalid_argument (its documented error).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tools/blend_case.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::ostringstream err;
  const oitref::Profile exact = oitref::exactProfile(), llvmpipe = oitref::parseProfile("llvmpipe");
  try {
    oitref::tools::forEachBlendCsvCase(in, err, "fuzz.csv", [&](int, const std::string&, const oitref::tools::BlendCase& c) {
      (void)oitref::tools::evaluate(c, exact);
      (void)oitref::tools::evaluate(c, llvmpipe);
    });
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
