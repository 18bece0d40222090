// glcheck's side-by-side timing (`glcheck scene --time N`): one method's frame rendered by oitref
// and by the GL driver in the same process, both already warm (the comparison ran them once),
// runs alternated so that a clock or cache drift hits both alike. oitref's frame is what
// Method::render costs: every pass, with its attachments taken from an AttachmentPool kept across
// runs. GL's frame is every pass and glFinish, in one GlFrame kept across runs (programs, geometry
// and textures made once, as an application keeps them). CPU time is the whole process's, so llvmpipe's worker threads count.
#pragma once

#include <string>
#include <vector>

#include "glcheck/gl_methods.h"

namespace oitref::glcheck {

struct TimingStats {
  double minWallMs = 0, medianWallMs = 0, minCpuMs = 0, medianCpuMs = 0;
};

// One kind of pass, its time summed over the frame (peeling's 32 "peel N" passes are one "peel"),
// median over the runs.
struct PassTiming {
  std::string kind;
  double medianMs = 0;
  int perFrame = 0;  // passes of this kind in a frame
};

struct MethodTiming {
  TimingStats oitref, gl;
  // The median over runs of oitref's CPU (wall) time over GL's in the same run: each ratio compares
  // two frames rendered one right after the other, so a change of the machine's speed between runs
  // (this project's machine swings by a third within seconds) cancels in it, where the ratio of the
  // two medians can take them from different phases.
  double pairedCpuRatio = 0, pairedWallRatio = 0;
  // oitref's passes as PassReport times them (steady clock around each pass); GL's by timer queries
  // (GL_TIME_ELAPSED, the driver's clock): GL's kinds are opaque, transparent, full-screen, composite.
  std::vector<PassTiming> oitrefPasses, glPasses;
  std::string sha256;  // of oitref's frame (frameHash, oitref/oit/frame.h), equal in every run or it throws
  double compositeTrafficBytes = 0;
};

// The machine's memory bandwidth for one thread: the best of a few memcpy calls of 256 MiB,
// counting each byte read and written (GB/s, 10^9 bytes).
double measureMemoryBandwidth();

// The least memory traffic of a frame's composite, which reads once every attachment the method
// declares as read by it (AttachmentDecl::readByComposite: not the depth buffer, not MBOIT's
// moments) and reads and writes the two presented targets (RGBA8 and the RGBA32F analysis copy):
// bytes. Over the bandwidth, the time below which no full-screen composite can go.
double compositeTrafficBytes(const std::vector<AttachmentDecl>& attachments, int width, int height);

// The median over i of a[i] / b[i] (same length, at least one).
double medianOfRatios(const std::vector<double>& a, const std::vector<double>& b);

MethodTiming timeMethod(const GlContext& context, const FrameContext& frame, Method& method, GlMethod glMethod,
                        const MethodOptions& options, int runs);

}  // namespace oitref::glcheck
