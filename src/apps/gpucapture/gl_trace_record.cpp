// The recording half of the GL trace (gpucapture/gl_trace.h): a function table that calls the
// driver and writes each call.
#include <cstring>
#include <ostream>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "gpucapture/gl_trace.h"
#include "gpucapture/gl_trace_ops.h"

namespace oitref::glcheck {
namespace {

using trace::kMagic;
using trace::Op;

// ---- recording ---------------------------------------------------------------------------------

struct Recorder {
  GlFunctions driver;
  std::ostream* out = nullptr;
  std::unordered_map<std::string, uint32_t> blobs;  // contents -> id: geometry repeats per frame

  template <typename T>
  void put(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out->write(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void op(Op o) { put(uint16_t(o)); }
  uint32_t blob(const void* data, size_t bytes) {
    std::string key(static_cast<const char*>(data), bytes);
    const auto found = blobs.find(key);
    if (found != blobs.end()) return found->second;
    const uint32_t id = uint32_t(blobs.size());
    op(Op::Blob);
    put(id);
    put(uint64_t(bytes));
    out->write(key.data(), std::streamsize(bytes));
    blobs.emplace(std::move(key), id);
    return id;
  }
  void names(GLsizei n, const GLuint* ids) {
    put(n);
    for (GLsizei i = 0; i < n; ++i) put(ids[i]);
  }
};
Recorder* gRecorder = nullptr;
Recorder& rec() { return *gRecorder; }

// Forwarding wrappers: R(Op, driver call) records the op with the listed scalars.
#define OITREF_PUT(x) rec().put(x);
#define OITREF_SIMPLE(name, params, args, ...)                \
  void APIENTRY name params {                                 \
    rec().op(Op::name);                                       \
    __VA_ARGS__                                               \
    rec().driver.name args;                                   \
  }

OITREF_SIMPLE(Enable, (GLenum a), (a), OITREF_PUT(a))
OITREF_SIMPLE(Disable, (GLenum a), (a), OITREF_PUT(a))
OITREF_SIMPLE(Enablei, (GLenum a, GLuint i), (a, i), OITREF_PUT(a) OITREF_PUT(i))
OITREF_SIMPLE(Disablei, (GLenum a, GLuint i), (a, i), OITREF_PUT(a) OITREF_PUT(i))
OITREF_SIMPLE(Viewport, (GLint x, GLint y, GLsizei w, GLsizei h), (x, y, w, h), OITREF_PUT(x) OITREF_PUT(y) OITREF_PUT(w) OITREF_PUT(h))
OITREF_SIMPLE(Finish, (), ())
OITREF_SIMPLE(PixelStorei, (GLenum p, GLint v), (p, v), OITREF_PUT(p) OITREF_PUT(v))
OITREF_SIMPLE(ReadBuffer, (GLenum b), (b), OITREF_PUT(b))
OITREF_SIMPLE(BindTexture, (GLenum t, GLuint id), (t, id), OITREF_PUT(t) OITREF_PUT(id))
OITREF_SIMPLE(ActiveTexture, (GLenum t), (t), OITREF_PUT(t))
OITREF_SIMPLE(TexStorage2D, (GLenum t, GLsizei l, GLenum f, GLsizei w, GLsizei h), (t, l, f, w, h),
              OITREF_PUT(t) OITREF_PUT(l) OITREF_PUT(f) OITREF_PUT(w) OITREF_PUT(h))
OITREF_SIMPLE(TexParameteri, (GLenum t, GLenum p, GLint v), (t, p, v), OITREF_PUT(t) OITREF_PUT(p) OITREF_PUT(v))
OITREF_SIMPLE(BindFramebuffer, (GLenum t, GLuint id), (t, id), OITREF_PUT(t) OITREF_PUT(id))
OITREF_SIMPLE(FramebufferTexture2D, (GLenum t, GLenum a, GLenum tt, GLuint id, GLint l), (t, a, tt, id, l),
              OITREF_PUT(t) OITREF_PUT(a) OITREF_PUT(tt) OITREF_PUT(id) OITREF_PUT(l))
OITREF_SIMPLE(ClearBufferfi, (GLenum b, GLint i, GLfloat d, GLint s), (b, i, d, s), OITREF_PUT(b) OITREF_PUT(i) OITREF_PUT(d) OITREF_PUT(s))
OITREF_SIMPLE(ColorMaski, (GLuint i, GLboolean r, GLboolean g, GLboolean b, GLboolean a), (i, r, g, b, a),
              OITREF_PUT(i) OITREF_PUT(r) OITREF_PUT(g) OITREF_PUT(b) OITREF_PUT(a))
OITREF_SIMPLE(DepthFunc, (GLenum f), (f), OITREF_PUT(f))
OITREF_SIMPLE(CullFace, (GLenum m), (m), OITREF_PUT(m))
OITREF_SIMPLE(FrontFace, (GLenum m), (m), OITREF_PUT(m))
OITREF_SIMPLE(DepthMask, (GLboolean m), (m), OITREF_PUT(m))
OITREF_SIMPLE(BlendEquationSeparatei, (GLuint i, GLenum a, GLenum b), (i, a, b), OITREF_PUT(i) OITREF_PUT(a) OITREF_PUT(b))
OITREF_SIMPLE(BlendFuncSeparatei, (GLuint i, GLenum a, GLenum b, GLenum c, GLenum d), (i, a, b, c, d),
              OITREF_PUT(i) OITREF_PUT(a) OITREF_PUT(b) OITREF_PUT(c) OITREF_PUT(d))
OITREF_SIMPLE(BlendColor, (GLfloat r, GLfloat g, GLfloat b, GLfloat a), (r, g, b, a), OITREF_PUT(r) OITREF_PUT(g) OITREF_PUT(b) OITREF_PUT(a))
OITREF_SIMPLE(CompileShader, (GLuint s), (s), OITREF_PUT(s))
OITREF_SIMPLE(DeleteShader, (GLuint s), (s), OITREF_PUT(s))
OITREF_SIMPLE(AttachShader, (GLuint p, GLuint s), (p, s), OITREF_PUT(p) OITREF_PUT(s))
OITREF_SIMPLE(LinkProgram, (GLuint p), (p), OITREF_PUT(p))
OITREF_SIMPLE(DeleteProgram, (GLuint p), (p), OITREF_PUT(p))
OITREF_SIMPLE(UseProgram, (GLuint p), (p), OITREF_PUT(p))
OITREF_SIMPLE(Uniform1i, (GLint l, GLint v), (l, v), OITREF_PUT(l) OITREF_PUT(v))
OITREF_SIMPLE(Uniform1f, (GLint l, GLfloat v), (l, v), OITREF_PUT(l) OITREF_PUT(v))
OITREF_SIMPLE(BindBuffer, (GLenum t, GLuint b), (t, b), OITREF_PUT(t) OITREF_PUT(b))
OITREF_SIMPLE(BindBufferBase, (GLenum t, GLuint i, GLuint b), (t, i, b), OITREF_PUT(t) OITREF_PUT(i) OITREF_PUT(b))
OITREF_SIMPLE(BindVertexArray, (GLuint v), (v), OITREF_PUT(v))
OITREF_SIMPLE(DrawArrays, (GLenum m, GLint f, GLsizei n), (m, f, n), OITREF_PUT(m) OITREF_PUT(f) OITREF_PUT(n))
OITREF_SIMPLE(EnableVertexAttribArray, (GLuint i), (i), OITREF_PUT(i))
OITREF_SIMPLE(MemoryBarrier, (GLbitfield b), (b), OITREF_PUT(b))
OITREF_SIMPLE(ProvokingVertex, (GLenum m), (m), OITREF_PUT(m))
OITREF_SIMPLE(CopyImageSubData,
              (GLuint s, GLenum st, GLint sl, GLint sx, GLint sy, GLint sz, GLuint d, GLenum dt, GLint dl, GLint dx, GLint dy,
               GLint dz, GLsizei w, GLsizei h, GLsizei depth),
              (s, st, sl, sx, sy, sz, d, dt, dl, dx, dy, dz, w, h, depth),
              OITREF_PUT(s) OITREF_PUT(st) OITREF_PUT(sl) OITREF_PUT(sx) OITREF_PUT(sy) OITREF_PUT(sz) OITREF_PUT(d)
                  OITREF_PUT(dt) OITREF_PUT(dl) OITREF_PUT(dx) OITREF_PUT(dy) OITREF_PUT(dz) OITREF_PUT(w) OITREF_PUT(h)
                      OITREF_PUT(depth))
#undef OITREF_SIMPLE
#undef OITREF_PUT

// Calls that create names: the driver's names are recorded, and mapped again on replay.
#define OITREF_GEN(name)                        \
  void APIENTRY name(GLsizei n, GLuint* ids) { \
    rec().driver.name(n, ids);                  \
    rec().op(Op::name);                         \
    rec().names(n, ids);                        \
  }
OITREF_GEN(GenTextures)
OITREF_GEN(GenFramebuffers)
OITREF_GEN(GenBuffers)
OITREF_GEN(GenVertexArrays)
#undef OITREF_GEN
#define OITREF_DELETE(name)                           \
  void APIENTRY name(GLsizei n, const GLuint* ids) { \
    rec().op(Op::name);                               \
    rec().names(n, ids);                              \
    rec().driver.name(n, ids);                        \
  }
OITREF_DELETE(DeleteTextures)
OITREF_DELETE(DeleteFramebuffers)
OITREF_DELETE(DeleteBuffers)
OITREF_DELETE(DeleteVertexArrays)
#undef OITREF_DELETE

GLuint APIENTRY CreateShader(GLenum type) {
  const GLuint s = rec().driver.CreateShader(type);
  rec().op(Op::CreateShader);
  rec().put(type);
  rec().put(s);
  return s;
}
GLuint APIENTRY CreateProgram() {
  const GLuint p = rec().driver.CreateProgram();
  rec().op(Op::CreateProgram);
  rec().put(p);
  return p;
}
void APIENTRY ShaderSource(GLuint s, GLsizei count, const GLchar* const* strings, const GLint* lengths) {
  std::string text;
  for (GLsizei i = 0; i < count; ++i) text += lengths && lengths[i] >= 0 ? std::string(strings[i], size_t(lengths[i])) : strings[i];
  const uint32_t id = rec().blob(text.data(), text.size());
  rec().op(Op::ShaderSource);
  rec().put(s);
  rec().put(id);
  rec().driver.ShaderSource(s, count, strings, lengths);
}
GLint APIENTRY GetUniformLocation(GLuint p, const GLchar* name) {
  const GLint location = rec().driver.GetUniformLocation(p, name);
  const uint32_t id = rec().blob(name, std::strlen(name));
  rec().op(Op::GetUniformLocation);
  rec().put(p);
  rec().put(id);
  rec().put(location);
  return location;
}
void APIENTRY Uniform4fv(GLint l, GLsizei n, const GLfloat* v) {
  const uint32_t id = rec().blob(v, size_t(n) * 16);
  rec().op(Op::Uniform4fv);
  rec().put(l);
  rec().put(n);
  rec().put(id);
  rec().driver.Uniform4fv(l, n, v);
}
void APIENTRY DrawBuffers(GLsizei n, const GLenum* buffers) {
  rec().op(Op::DrawBuffers);
  rec().put(n);
  for (GLsizei i = 0; i < n; ++i) rec().put(buffers[i]);
  rec().driver.DrawBuffers(n, buffers);
}
void APIENTRY ClearBufferfv(GLenum buffer, GLint i, const GLfloat* v) {
  rec().op(Op::ClearBufferfv);
  rec().put(buffer);
  rec().put(i);
  for (int c = 0; c < (buffer == GL_COLOR ? 4 : 1); ++c) rec().put(v[c]);
  rec().driver.ClearBufferfv(buffer, i, v);
}

// RGBA bytes only (what oitref uploads), rows tightly packed: the texels go into the trace as a blob.
void APIENTRY TexSubImage2D(GLenum target, GLint level, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type,
                            const void* pixels) {
  if (format != GL_RGBA || type != GL_UNSIGNED_BYTE || !pixels)
    throw std::runtime_error("trace: glTexSubImage2D is recorded for GL_RGBA / GL_UNSIGNED_BYTE texels only");
  const uint32_t id = rec().blob(pixels, size_t(w) * size_t(h) * 4);
  rec().op(Op::TexSubImage2D);
  rec().put(target), rec().put(level), rec().put(x), rec().put(y), rec().put(w), rec().put(h), rec().put(id);
  rec().driver.TexSubImage2D(target, level, x, y, w, h, format, type, pixels);
}

void APIENTRY BufferData(GLenum target, GLsizeiptr size, const void* data, GLenum usage) {
  const uint32_t id = data ? rec().blob(data, size_t(size)) : UINT32_MAX;
  rec().op(Op::BufferData);
  rec().put(target);
  rec().put(int64_t(size));
  rec().put(id);
  rec().put(usage);
  rec().driver.BufferData(target, size, data, usage);
}
void APIENTRY DrawElements(GLenum mode, GLsizei count, GLenum type, const void* offset) {
  rec().op(Op::DrawElements);
  rec().put(mode);
  rec().put(count);
  rec().put(type);
  rec().put(uint64_t(reinterpret_cast<uintptr_t>(offset)));
  rec().driver.DrawElements(mode, count, type, offset);
}
void APIENTRY VertexAttribPointer(GLuint i, GLint size, GLenum type, GLboolean norm, GLsizei stride, const void* offset) {
  rec().op(Op::VertexAttribPointer);
  rec().put(i);
  rec().put(size);
  rec().put(type);
  rec().put(norm);
  rec().put(stride);
  rec().put(uint64_t(reinterpret_cast<uintptr_t>(offset)));
  rec().driver.VertexAttribPointer(i, size, type, norm, stride, offset);
}
void APIENTRY ReadPixels(GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void* data) {
  rec().op(Op::ReadPixels);
  for (GLint v : {x, y, GLint(w), GLint(h)}) rec().put(v);
  rec().put(format);
  rec().put(type);
  rec().driver.ReadPixels(x, y, w, h, format, type, data);
}

}  // namespace

GlFunctions recordingFunctions(const GlFunctions& driver, std::ostream& out) {
  static Recorder recorder;
  recorder = Recorder{};
  recorder.driver = driver;
  recorder.out = &out;
  gRecorder = &recorder;
  out.write(kMagic, sizeof kMagic);
  GlFunctions f = driver;  // queries pass straight through
#define OITREF_WRAP(type, name) f.name = name;
  OITREF_WRAP(, Enable) OITREF_WRAP(, Disable) OITREF_WRAP(, Enablei) OITREF_WRAP(, Disablei) OITREF_WRAP(, Viewport)
  OITREF_WRAP(, Finish) OITREF_WRAP(, PixelStorei) OITREF_WRAP(, ReadPixels) OITREF_WRAP(, ReadBuffer)
  OITREF_WRAP(, GenTextures) OITREF_WRAP(, DeleteTextures) OITREF_WRAP(, BindTexture) OITREF_WRAP(, ActiveTexture)
  OITREF_WRAP(, TexStorage2D) OITREF_WRAP(, TexSubImage2D) OITREF_WRAP(, TexParameteri) OITREF_WRAP(, GenFramebuffers) OITREF_WRAP(, DeleteFramebuffers)
  OITREF_WRAP(, BindFramebuffer) OITREF_WRAP(, FramebufferTexture2D) OITREF_WRAP(, DrawBuffers) OITREF_WRAP(, ClearBufferfv)
  OITREF_WRAP(, ClearBufferfi) OITREF_WRAP(, ColorMaski) OITREF_WRAP(, DepthFunc) OITREF_WRAP(, DepthMask)
  OITREF_WRAP(, CullFace) OITREF_WRAP(, FrontFace)
  OITREF_WRAP(, BlendEquationSeparatei) OITREF_WRAP(, BlendFuncSeparatei) OITREF_WRAP(, BlendColor)
  OITREF_WRAP(, CreateShader) OITREF_WRAP(, ShaderSource) OITREF_WRAP(, CompileShader) OITREF_WRAP(, DeleteShader)
  OITREF_WRAP(, CreateProgram) OITREF_WRAP(, AttachShader) OITREF_WRAP(, LinkProgram) OITREF_WRAP(, DeleteProgram)
  OITREF_WRAP(, UseProgram) OITREF_WRAP(, GetUniformLocation) OITREF_WRAP(, Uniform1i) OITREF_WRAP(, Uniform1f)
  OITREF_WRAP(, Uniform4fv) OITREF_WRAP(, GenBuffers) OITREF_WRAP(, DeleteBuffers) OITREF_WRAP(, BindBuffer)
  OITREF_WRAP(, BufferData) OITREF_WRAP(, BindBufferBase) OITREF_WRAP(, GenVertexArrays) OITREF_WRAP(, DeleteVertexArrays)
  OITREF_WRAP(, BindVertexArray) OITREF_WRAP(, DrawArrays) OITREF_WRAP(, DrawElements) OITREF_WRAP(, VertexAttribPointer)
  OITREF_WRAP(, EnableVertexAttribArray) OITREF_WRAP(, CopyImageSubData) OITREF_WRAP(, MemoryBarrier)
  OITREF_WRAP(, ProvokingVertex)
#undef OITREF_WRAP
  return f;
}

}  // namespace oitref::glcheck
