// Storage for the largest scattered buffers (the A-buffer's fragments, gigabytes written a record
// at a time in pixel lists all over the buffer) on the kernel's 2 MiB pages where it offers them
// (Linux's transparent huge pages in "madvise" mode, as on Debian 12): with 4 KiB pages, every
// scattered record missed the TLB (a nested page walk in a virtual machine), and the first frame's
// page faults took longer than its rendering. Values are never affected, only where they live.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace oitref::util {

// v.reserve(n) (v keeps its elements), with the whole 2 MiB pages of a new allocation advised as
// huge before anything touches them. No effect on a vector that already holds n.
template <typename T>
void reserveOnHugePages(std::vector<T>& v, size_t n) {
  if (n <= v.capacity()) return;
  v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHuge = uintptr_t(1) << 21;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(v.data()) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = reinterpret_cast<uintptr_t>(v.data() + n) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // advice: failure is harmless
#endif
}

}  // namespace oitref::util
