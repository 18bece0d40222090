// GL versions of oitref's methods for glcheck's scene mode: the passes, attachments, formats and
// blend states of src/oit/methods/<name>.cpp, in the same order, with GLSL where the C++ has lambdas.
// Where the GLSL cannot say what the C++ says, the file says so (e.g. MBOIT's ln and exp are
// the driver's fp32 builtins, not det_math.h's).
#pragma once

#include <string>
#include <vector>

#include "glcheck/gl_frame.h"

namespace oitref::glcheck {

// Renders the method's frame on GL; returns the attachment that holds the presented image
// ("opaque", or "final" for wsum). The analysis copy is "analysis".
using GlMethod = std::string (*)(GlFrame& frame, const MethodOptions& options);

// The A-buffer's GL version (gl_abuffer.cpp).
std::string abuffer(GlFrame& frame, const MethodOptions& options);

// nullptr when the method has no GL version.
GlMethod findGlMethod(const std::string& name);
// The methods with a GL version, in the order `oitref methods` lists them.
std::vector<std::string> glMethodNames();

}  // namespace oitref::glcheck
