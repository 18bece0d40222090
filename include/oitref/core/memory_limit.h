// Memory limits: what a frame or a loaded file may take (--memory-limit), and how sizes are
// written in the messages that refuse more.
#pragma once

#include <cstdint>
#include <string>

namespace oitref {

// Half of the machine's physical memory: the default --memory-limit.
uint64_t defaultMemoryLimit();
// "1.5 MiB" style.
std::string formatBytes(uint64_t bytes);

}  // namespace oitref
