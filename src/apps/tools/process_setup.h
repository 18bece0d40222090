// Process-wide settings of the oitref programs.
#pragma once

namespace oitref::tools {

// Every frame allocates its attachments anew, and at 1920×1080 the RGBA32F analysis copy alone
// is 33 MB — above glibc's largest automatic mmap threshold (32 MiB), so each frame mmapped it
// fresh and paid a page fault per 4 KiB page (a quarter of a single-threaded opaque frame at
// 1080p, measured with perf). Keeping blocks up to 1 GiB in the heap, and not trimming it,
// lets the next frame reuse the memory. Only speed changes, never a result.
void keepLargeAllocations();

}  // namespace oitref::tools
