// glcheck's side-by-side timing (`glcheck scene --time N`): one method's frame rendered by oitref
// and by the GL driver in the same process, both already warm (the comparison ran them once),
// runs alternated so that a clock or cache drift hits both alike. oitref's frame is what
// Method::render costs: every pass, with its attachments taken from an AttachmentPool kept across
// runs. GL's frame is every pass and glFinish, in one GlFrame kept across runs (programs, geometry
// and textures made once, as an application keeps them). CPU time is the whole process's, so llvmpipe's worker threads count.
#pragma once

#include <string>

#include "glcheck/gl_methods.h"

namespace oitref::glcheck {

struct TimingStats {
  double minWallMs = 0, medianWallMs = 0, minCpuMs = 0, medianCpuMs = 0;
};

struct MethodTiming {
  TimingStats oitref, gl;
  std::string sha256;  // of oitref's frame (tools::frameHash), equal in every run or it throws
};

MethodTiming timeMethod(const GlContext& context, const FrameContext& frame, Method& method, GlMethod glMethod,
                        const MethodOptions& options, int runs);

}  // namespace oitref::glcheck
