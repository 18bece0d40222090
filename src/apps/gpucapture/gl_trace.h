// A GL command trace: every call glcheck makes, recorded where oitref runs (on any driver) and
// replayed where the GPU is by oitref-gpu-capture, which writes back what each glReadPixels read.
// glcheck then runs the same frames again with those texels in place of its own driver's, so a
// whole frame on a GPU machine is compared with oitref without oitref on that machine.
//
//   record:   recordingFunctions(driver, trace) — a function table that calls the driver and
//             writes each call, its scalars, the data it passes (blobs, each stored once) and
//             the object names it creates (mapped again on replay);
//   replay:   replayTrace(driver, trace, readbacks) — the calls on this machine's driver, the
//             bytes of every glReadPixels appended to `readbacks`;
//   compare:  substitutingFunctions(driver, readbacks) — calls the driver, but every
//             glReadPixels returns the next recorded read instead (its size must match).
//
// Only EGL/GL headers and the standard library: this file builds into the standalone program.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "glcheck/gl_functions.h"

namespace oitref::glcheck {

// Bytes per pixel of glReadPixels for a format/type pair (throws for others).
size_t readPixelBytes(GLenum format, GLenum type);

// Records into `out` (binary). Only one recording may be active; it ends with the table's use.
GlFunctions recordingFunctions(const GlFunctions& driver, std::ostream& out);

// Replays a trace; returns the number of calls. Throws naming the call on a malformed trace.
size_t replayTrace(const GlFunctions& driver, std::istream& trace, std::ostream& readbacks);

// Every glReadPixels answers from `readbacks` in order (each must have the requested size).
GlFunctions substitutingFunctions(const GlFunctions& driver, std::istream& readbacks);

}  // namespace oitref::glcheck
