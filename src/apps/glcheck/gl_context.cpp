#include "glcheck/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <stdexcept>
#include <vector>

namespace oitref::glcheck {

struct GlContext::Egl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

namespace {

std::string eglErrorText(const char* step) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s failed (EGL error 0x%04x)", step, unsigned(eglGetError()));
  return buf;
}

// Initialises `display` and creates a current 4.3 core context on it; false (display released)
// when this display cannot give one.
bool makeContext(EGLDisplay display, EGLContext& context, std::string& why) {
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor)) {
    why = eglErrorText("eglInitialize");
    return false;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why = eglErrorText("eglBindAPI(EGL_OPENGL_API)");
    eglTerminate(display);
    return false;
  }
  const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count == 0) config = nullptr;
  const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  // Without a surface-less config, EGL_KHR_no_config_context lets us pass no config at all.
  context = eglCreateContext(display, config ? config : EGLConfig(nullptr), EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT) {
    why = eglErrorText("eglCreateContext(OpenGL 4.3 core)");
    eglTerminate(display);
    return false;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    why = eglErrorText("eglMakeCurrent without a surface");
    eglDestroyContext(display, context);
    eglTerminate(display);
    return false;
  }
  return true;
}

}  // namespace

GlContext::GlContext() : egl_(std::make_unique<Egl>()) {
  std::string why;
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (getPlatformDisplay && queryDevices) {
    EGLint n = 0;
    queryDevices(0, nullptr, &n);
    std::vector<EGLDeviceEXT> devices(size_t(std::max(n, 0)));
    if (n > 0 && queryDevices(n, devices.data(), &n)) {
      for (EGLDeviceEXT device : devices) {
        EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
        if (makeContext(d, egl_->context, why)) {
          egl_->display = d;
          platform_ = "device";
          break;
        }
      }
    }
  }
  if (egl_->display == EGL_NO_DISPLAY && getPlatformDisplay) {
    EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (makeContext(d, egl_->context, why)) {
      egl_->display = d;
      platform_ = "surfaceless";
    }
  }
  if (egl_->display == EGL_NO_DISPLAY)
    throw std::runtime_error("no headless OpenGL 4.3 core context through EGL (device and surfaceless platforms): " +
                             (why.empty() ? std::string("eglGetPlatformDisplayEXT unavailable") : why));
#define OITREF_GL_LOAD(type, name)                                                        \
  gl_.name = reinterpret_cast<type>(eglGetProcAddress("gl" #name));                      \
  if (!gl_.name) throw std::runtime_error("the OpenGL driver lacks gl" #name);
  OITREF_GL_FUNCTIONS(OITREF_GL_LOAD)
#undef OITREF_GL_LOAD
  driver_ = gl_;
}

GlContext::~GlContext() {
  if (egl_->display != EGL_NO_DISPLAY) {
    eglMakeCurrent(egl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(egl_->display, egl_->context);
    eglTerminate(egl_->display);
  }
}

static std::string glString(const GlFunctions& gl, GLenum name) {
  const GLubyte* s = gl.GetString(name);
  return s ? reinterpret_cast<const char*>(s) : "?";
}
std::string GlContext::renderer() const { return glString(gl_, GL_RENDERER); }
std::string GlContext::version() const { return glString(gl_, GL_VERSION); }
std::string GlContext::vendor() const { return glString(gl_, GL_VENDOR); }

void GlContext::check(const char* what) const {
  const GLenum e = gl_.GetError();
  if (e != GL_NO_ERROR) {
    char buf[64];
    std::snprintf(buf, sizeof buf, " (GL error 0x%04x)", unsigned(e));
    throw std::runtime_error(std::string(what) + buf);
  }
}

void requireCompiled(const GlFunctions& gl, unsigned shader, const std::string& what) {
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return;
  char log[4096] = {};
  gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
  throw std::runtime_error(what + " does not compile:\n" + log);
}

void requireLinked(const GlFunctions& gl, unsigned program, const std::string& what) {
  GLint ok = 0;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok) return;
  char log[4096] = {};
  gl.GetProgramInfoLog(program, sizeof log, nullptr, log);
  throw std::runtime_error(what + " does not link:\n" + log);
}

static unsigned compile(const GlFunctions& gl, GLenum type, const std::string& source) {
  const GLuint s = gl.CreateShader(type);
  const char* text = source.c_str();
  gl.ShaderSource(s, 1, &text, nullptr);
  gl.CompileShader(s);
  try {
    requireCompiled(gl, s, type == GL_VERTEX_SHADER ? "vertex shader" : "fragment shader");
  } catch (...) {
    gl.DeleteShader(s);
    throw;
  }
  return s;
}

unsigned linkProgram(const GlFunctions& gl, const std::string& vertex, const std::string& fragment) {
  const GLuint vs = compile(gl, GL_VERTEX_SHADER, vertex), fs = compile(gl, GL_FRAGMENT_SHADER, fragment);
  const GLuint p = gl.CreateProgram();
  gl.AttachShader(p, vs);
  gl.AttachShader(p, fs);
  gl.LinkProgram(p);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  try {
    requireLinked(gl, p, "program");
  } catch (...) {
    gl.DeleteProgram(p);
    throw;
  }
  return p;
}

}  // namespace oitref::glcheck
