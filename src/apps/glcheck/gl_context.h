// A headless OpenGL 4.3+ core context through EGL: no window, no X server. EGL's device platform
// first (EGL_EXT_platform_device, e.g. Mesa's software device), then the surfaceless platform
// (EGL_MESA_platform_surfaceless). Rendering goes to framebuffer objects only.
#pragma once

#include <memory>
#include <string>

#include "glcheck/gl_functions.h"

namespace oitref::glcheck {

class GlContext {
 public:
  // Throws std::runtime_error saying which step failed (no EGL display, no 4.3 core context...).
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  const GlFunctions& gl() const { return gl_; }
  // The driver's own entry points, and a table to use instead of them from now on (a recording
  // or substituting one, gpucapture/gl_trace.h).
  const GlFunctions& driver() const { return driver_; }
  void setFunctions(const GlFunctions& functions) { gl_ = functions; }
  std::string renderer() const;   // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version() const;    // GL_VERSION
  std::string vendor() const;     // GL_VENDOR
  const std::string& platform() const { return platform_; }  // "device" or "surfaceless"

  // Throws when glGetError reports an error, naming `what`.
  void check(const char* what) const;

 private:
  struct Egl;
  std::unique_ptr<Egl> egl_;
  GlFunctions gl_, driver_;
  std::string platform_;
};

// Throw with the info log, naming `what`, when a shader did not compile / a program did not link.
void requireCompiled(const GlFunctions& gl, unsigned shader, const std::string& what);
void requireLinked(const GlFunctions& gl, unsigned program, const std::string& what);

// Compiles and links a program from GLSL sources (vertex + fragment); throws with the info log.
unsigned linkProgram(const GlFunctions& gl, const std::string& vertex, const std::string& fragment);

}  // namespace oitref::glcheck
