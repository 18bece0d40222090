#include "tools/process_setup.h"

#include <malloc.h>

namespace oitref::tools {

void keepLargeAllocations() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

}  // namespace oitref::tools
