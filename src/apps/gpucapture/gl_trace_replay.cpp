// The replaying half of the GL trace (gpucapture/gl_trace.h), and the substituting reads.
#include <algorithm>
#include <cstring>
#include <istream>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "glcheck/gl_context.h"
#include "gpucapture/gl_trace.h"
#include "gpucapture/gl_trace_ops.h"

namespace oitref::glcheck {
namespace {

using trace::kMagic;
using trace::Op;

// ---- reading -----------------------------------------------------------------------------------

struct Reader {
  std::istream& in;
  size_t calls = 0;
  template <typename T>
  T get() {
    T v;
    if (!in.read(reinterpret_cast<char*>(&v), sizeof v)) throw std::runtime_error("GL trace ends inside a call");
    return v;
  }
};

struct Replay {
  GlFunctions gl;
  std::vector<std::string> blobs;
  std::unordered_map<GLuint, GLuint> textures, framebuffers, buffers, arrays, shaders, programs;
  std::map<std::pair<GLuint, GLint>, GLint> locations;  // (recorded program, recorded location)
  GLuint program = 0;                                   // the recorded program in use

  static GLuint mapped(const std::unordered_map<GLuint, GLuint>& m, GLuint id, const char* what) {
    if (id == 0) return 0;
    const auto found = m.find(id);
    if (found == m.end()) throw std::runtime_error(std::string("GL trace uses an unknown ") + what + " name");
    return found->second;
  }
  const std::string& blob(uint32_t id) const {
    if (id >= blobs.size()) throw std::runtime_error("GL trace refers to a missing blob");
    return blobs[id];
  }
  GLint location(GLint recorded) const {
    if (recorded < 0) return recorded;
    const auto found = locations.find({program, recorded});
    if (found == locations.end()) throw std::runtime_error("GL trace sets a uniform it never located");
    return found->second;
  }
};

void genNames(Reader& r, std::unordered_map<GLuint, GLuint>& m, void(APIENTRY* gen)(GLsizei, GLuint*)) {
  const GLsizei n = r.get<GLsizei>();
  std::vector<GLuint> mine(size_t(std::max(n, 0)));
  gen(n, mine.data());
  for (GLsizei i = 0; i < n; ++i) m[r.get<GLuint>()] = mine[size_t(i)];
}
void deleteNames(Reader& r, std::unordered_map<GLuint, GLuint>& m, void(APIENTRY* del)(GLsizei, const GLuint*),
                 const char* what) {
  const GLsizei n = r.get<GLsizei>();
  std::vector<GLuint> mine;
  for (GLsizei i = 0; i < n; ++i) {
    const GLuint recorded = r.get<GLuint>();
    mine.push_back(Replay::mapped(m, recorded, what));
    m.erase(recorded);
  }
  del(n, mine.data());
}

// ---- substituting reads ------------------------------------------------------------------------

struct Substitute {
  GlFunctions driver;
  std::istream* readbacks = nullptr;
};
Substitute* gSubstitute = nullptr;

void APIENTRY SubstitutedReadPixels(GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void* data) {
  gSubstitute->driver.ReadPixels(x, y, w, h, format, type, data);
  uint64_t bytes = 0;
  if (!gSubstitute->readbacks->read(reinterpret_cast<char*>(&bytes), sizeof bytes))
    throw std::runtime_error("the recorded GPU reads end before this frame's (was the trace recorded with the same options?)");
  const uint64_t expected = uint64_t(w) * uint64_t(h) * readPixelBytes(format, type);
  if (bytes != expected)
    throw std::runtime_error("a recorded GPU read has " + std::to_string(bytes) + " bytes where this frame reads " +
                             std::to_string(expected) + " (was the trace recorded with the same options?)");
  gSubstitute->readbacks->read(static_cast<char*>(data), std::streamsize(bytes));
}

}  // namespace

size_t readPixelBytes(GLenum format, GLenum type) {
  if (type == GL_UNSIGNED_INT_2_10_10_10_REV || type == GL_UNSIGNED_INT_10F_11F_11F_REV) return 4;
  const size_t channels = format == GL_RED || format == GL_DEPTH_COMPONENT ? 1 : format == GL_RG ? 2 : format == GL_RGB ? 3 : format == GL_RGBA ? 4 : 0;
  const size_t bytes = type == GL_UNSIGNED_BYTE ? 1 : type == GL_UNSIGNED_SHORT || type == GL_HALF_FLOAT ? 2 : type == GL_FLOAT ? 4 : 0;
  if (!channels || !bytes) throw std::invalid_argument("glReadPixels format/type pair the GL trace does not know");
  return channels * bytes;
}

size_t replayTrace(const GlFunctions& driver, std::istream& trace, std::ostream& readbacks) {
  char magic[sizeof kMagic];
  if (!trace.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw std::runtime_error("not an oitref GL trace (no OITRGLT1 header)");
  Reader r{trace};
  Replay s;
  s.gl = driver;
  const GlFunctions& gl = driver;
  uint16_t code;
  while (trace.read(reinterpret_cast<char*>(&code), sizeof code)) {
    ++r.calls;
    switch (Op(code)) {
      case Op::Blob: {
        const uint32_t id = r.get<uint32_t>();
        const uint64_t bytes = r.get<uint64_t>();
        if (id != s.blobs.size()) throw std::runtime_error("GL trace blobs out of order");
        std::string b(size_t(bytes), '\0');
        if (!trace.read(b.data(), std::streamsize(bytes))) throw std::runtime_error("GL trace ends inside a blob");
        s.blobs.push_back(std::move(b));
        break;
      }
      case Op::Enable: gl.Enable(r.get<GLenum>()); break;
      case Op::Disable: gl.Disable(r.get<GLenum>()); break;
      case Op::Enablei: { const GLenum a = r.get<GLenum>(); gl.Enablei(a, r.get<GLuint>()); break; }
      case Op::Disablei: { const GLenum a = r.get<GLenum>(); gl.Disablei(a, r.get<GLuint>()); break; }
      case Op::Viewport: {
        const GLint x = r.get<GLint>(), y = r.get<GLint>();
        const GLsizei w = r.get<GLsizei>(), h = r.get<GLsizei>();
        gl.Viewport(x, y, w, h);
        break;
      }
      case Op::Finish: gl.Finish(); break;
      case Op::PixelStorei: { const GLenum p = r.get<GLenum>(); gl.PixelStorei(p, r.get<GLint>()); break; }
      case Op::ReadBuffer: gl.ReadBuffer(r.get<GLenum>()); break;
      case Op::ReadPixels: {
        GLint v[4];
        for (GLint& x : v) x = r.get<GLint>();
        const GLenum format = r.get<GLenum>(), type = r.get<GLenum>();
        const uint64_t bytes = uint64_t(v[2]) * uint64_t(v[3]) * readPixelBytes(format, type);
        std::vector<char> data(static_cast<size_t>(bytes));
        gl.ReadPixels(v[0], v[1], v[2], v[3], format, type, data.data());
        readbacks.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
        readbacks.write(data.data(), std::streamsize(bytes));
        break;
      }
      case Op::GenTextures: genNames(r, s.textures, gl.GenTextures); break;
      case Op::GenFramebuffers: genNames(r, s.framebuffers, gl.GenFramebuffers); break;
      case Op::GenBuffers: genNames(r, s.buffers, gl.GenBuffers); break;
      case Op::GenVertexArrays: genNames(r, s.arrays, gl.GenVertexArrays); break;
      case Op::DeleteTextures: deleteNames(r, s.textures, gl.DeleteTextures, "texture"); break;
      case Op::DeleteFramebuffers: deleteNames(r, s.framebuffers, gl.DeleteFramebuffers, "framebuffer"); break;
      case Op::DeleteBuffers: deleteNames(r, s.buffers, gl.DeleteBuffers, "buffer"); break;
      case Op::DeleteVertexArrays: deleteNames(r, s.arrays, gl.DeleteVertexArrays, "vertex array"); break;
      case Op::BindTexture: {
        const GLenum t = r.get<GLenum>();
        gl.BindTexture(t, Replay::mapped(s.textures, r.get<GLuint>(), "texture"));
        break;
      }
      case Op::ActiveTexture: gl.ActiveTexture(r.get<GLenum>()); break;
      case Op::TexStorage2D: {
        const GLenum t = r.get<GLenum>();
        const GLsizei l = r.get<GLsizei>();
        const GLenum f = r.get<GLenum>();
        const GLsizei w = r.get<GLsizei>(), h = r.get<GLsizei>();
        gl.TexStorage2D(t, l, f, w, h);
        break;
      }
      case Op::TexSubImage2D: {
        const GLenum t = r.get<GLenum>();
        const GLint l = r.get<GLint>(), x = r.get<GLint>(), y = r.get<GLint>();
        const GLsizei w = r.get<GLsizei>(), h = r.get<GLsizei>();
        const uint32_t id = r.get<uint32_t>();
        gl.TexSubImage2D(t, l, x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, s.blob(id).data());
        break;
      }
      case Op::TexParameteri: {
        const GLenum t = r.get<GLenum>(), p = r.get<GLenum>();
        gl.TexParameteri(t, p, r.get<GLint>());
        break;
      }
      case Op::BindFramebuffer: {
        const GLenum t = r.get<GLenum>();
        gl.BindFramebuffer(t, Replay::mapped(s.framebuffers, r.get<GLuint>(), "framebuffer"));
        break;
      }
      case Op::FramebufferTexture2D: {
        const GLenum t = r.get<GLenum>(), a = r.get<GLenum>(), tt = r.get<GLenum>();
        const GLuint id = Replay::mapped(s.textures, r.get<GLuint>(), "texture");
        gl.FramebufferTexture2D(t, a, tt, id, r.get<GLint>());
        break;
      }
      case Op::DrawBuffers: {
        const GLsizei n = r.get<GLsizei>();
        std::vector<GLenum> b;
        for (GLsizei i = 0; i < n; ++i) b.push_back(r.get<GLenum>());
        gl.DrawBuffers(n, b.data());
        break;
      }
      case Op::ClearBufferfv: {
        const GLenum b = r.get<GLenum>();
        const GLint i = r.get<GLint>();
        GLfloat v[4] = {};
        for (int c = 0; c < (b == GL_COLOR ? 4 : 1); ++c) v[c] = r.get<GLfloat>();
        gl.ClearBufferfv(b, i, v);
        break;
      }
      case Op::ClearBufferfi: {
        const GLenum b = r.get<GLenum>();
        const GLint i = r.get<GLint>();
        const GLfloat d = r.get<GLfloat>();
        gl.ClearBufferfi(b, i, d, r.get<GLint>());
        break;
      }
      case Op::ColorMaski: {
        const GLuint i = r.get<GLuint>();
        GLboolean m[4];
        for (GLboolean& x : m) x = r.get<GLboolean>();
        gl.ColorMaski(i, m[0], m[1], m[2], m[3]);
        break;
      }
      case Op::DepthFunc: gl.DepthFunc(r.get<GLenum>()); break;
      case Op::CullFace: gl.CullFace(r.get<GLenum>()); break;
      case Op::FrontFace: gl.FrontFace(r.get<GLenum>()); break;
      case Op::DepthMask: gl.DepthMask(r.get<GLboolean>()); break;
      case Op::BlendEquationSeparatei: {
        const GLuint i = r.get<GLuint>();
        const GLenum a = r.get<GLenum>();
        gl.BlendEquationSeparatei(i, a, r.get<GLenum>());
        break;
      }
      case Op::BlendFuncSeparatei: {
        const GLuint i = r.get<GLuint>();
        GLenum f[4];
        for (GLenum& x : f) x = r.get<GLenum>();
        gl.BlendFuncSeparatei(i, f[0], f[1], f[2], f[3]);
        break;
      }
      case Op::BlendColor: {
        GLfloat c[4];
        for (GLfloat& x : c) x = r.get<GLfloat>();
        gl.BlendColor(c[0], c[1], c[2], c[3]);
        break;
      }
      case Op::CreateShader: {
        const GLenum type = r.get<GLenum>();
        s.shaders[r.get<GLuint>()] = gl.CreateShader(type);
        break;
      }
      case Op::ShaderSource: {
        const GLuint sh = Replay::mapped(s.shaders, r.get<GLuint>(), "shader");
        const std::string& text = s.blob(r.get<uint32_t>());
        const GLchar* p = text.c_str();
        gl.ShaderSource(sh, 1, &p, nullptr);
        break;
      }
      case Op::CompileShader: {
        const GLuint sh = Replay::mapped(s.shaders, r.get<GLuint>(), "shader");
        gl.CompileShader(sh);
        requireCompiled(gl, sh, "a traced shader");
        break;
      }
      case Op::DeleteShader: {
        const GLuint recorded = r.get<GLuint>();
        gl.DeleteShader(Replay::mapped(s.shaders, recorded, "shader"));
        s.shaders.erase(recorded);
        break;
      }
      case Op::CreateProgram: s.programs[r.get<GLuint>()] = gl.CreateProgram(); break;
      case Op::AttachShader: {
        const GLuint p = Replay::mapped(s.programs, r.get<GLuint>(), "program");
        gl.AttachShader(p, Replay::mapped(s.shaders, r.get<GLuint>(), "shader"));
        break;
      }
      case Op::LinkProgram: {
        const GLuint p = Replay::mapped(s.programs, r.get<GLuint>(), "program");
        gl.LinkProgram(p);
        requireLinked(gl, p, "a traced program");
        break;
      }
      case Op::DeleteProgram: {
        const GLuint recorded = r.get<GLuint>();
        gl.DeleteProgram(Replay::mapped(s.programs, recorded, "program"));
        s.programs.erase(recorded);
        break;
      }
      case Op::UseProgram: {
        s.program = r.get<GLuint>();
        gl.UseProgram(Replay::mapped(s.programs, s.program, "program"));
        break;
      }
      case Op::GetUniformLocation: {
        const GLuint recordedProgram = r.get<GLuint>();
        const std::string& name = s.blob(r.get<uint32_t>());
        const GLint recorded = r.get<GLint>();
        s.locations[{recordedProgram, recorded}] =
            gl.GetUniformLocation(Replay::mapped(s.programs, recordedProgram, "program"), name.c_str());
        break;
      }
      case Op::Uniform1i: { const GLint l = s.location(r.get<GLint>()); gl.Uniform1i(l, r.get<GLint>()); break; }
      case Op::Uniform1f: { const GLint l = s.location(r.get<GLint>()); gl.Uniform1f(l, r.get<GLfloat>()); break; }
      case Op::Uniform4fv: {
        const GLint l = s.location(r.get<GLint>());
        const GLsizei n = r.get<GLsizei>();
        gl.Uniform4fv(l, n, reinterpret_cast<const GLfloat*>(s.blob(r.get<uint32_t>()).data()));
        break;
      }
      case Op::BindBuffer: {
        const GLenum t = r.get<GLenum>();
        gl.BindBuffer(t, Replay::mapped(s.buffers, r.get<GLuint>(), "buffer"));
        break;
      }
      case Op::BufferData: {
        const GLenum t = r.get<GLenum>();
        const int64_t size = r.get<int64_t>();
        const uint32_t id = r.get<uint32_t>();
        const GLenum usage = r.get<GLenum>();
        gl.BufferData(t, GLsizeiptr(size), id == UINT32_MAX ? nullptr : s.blob(id).data(), usage);
        break;
      }
      case Op::BindBufferBase: {
        const GLenum t = r.get<GLenum>();
        const GLuint i = r.get<GLuint>();
        gl.BindBufferBase(t, i, Replay::mapped(s.buffers, r.get<GLuint>(), "buffer"));
        break;
      }
      case Op::BindVertexArray: gl.BindVertexArray(Replay::mapped(s.arrays, r.get<GLuint>(), "vertex array")); break;
      case Op::DrawArrays: {
        const GLenum m = r.get<GLenum>();
        const GLint f = r.get<GLint>();
        gl.DrawArrays(m, f, r.get<GLsizei>());
        break;
      }
      case Op::DrawElements: {
        const GLenum m = r.get<GLenum>();
        const GLsizei n = r.get<GLsizei>();
        const GLenum t = r.get<GLenum>();
        gl.DrawElements(m, n, t, reinterpret_cast<const void*>(uintptr_t(r.get<uint64_t>())));
        break;
      }
      case Op::VertexAttribPointer: {
        const GLuint i = r.get<GLuint>();
        const GLint size = r.get<GLint>();
        const GLenum t = r.get<GLenum>();
        const GLboolean n = r.get<GLboolean>();
        const GLsizei stride = r.get<GLsizei>();
        gl.VertexAttribPointer(i, size, t, n, stride, reinterpret_cast<const void*>(uintptr_t(r.get<uint64_t>())));
        break;
      }
      case Op::EnableVertexAttribArray: gl.EnableVertexAttribArray(r.get<GLuint>()); break;
      case Op::CopyImageSubData: {
        GLuint src = Replay::mapped(s.textures, r.get<GLuint>(), "texture");
        const GLenum st = r.get<GLenum>();
        GLint a[4];
        for (GLint& x : a) x = r.get<GLint>();
        const GLuint dst = Replay::mapped(s.textures, r.get<GLuint>(), "texture");
        const GLenum dt = r.get<GLenum>();
        GLint b[4];
        for (GLint& x : b) x = r.get<GLint>();
        const GLsizei w = r.get<GLsizei>(), h = r.get<GLsizei>(), d = r.get<GLsizei>();
        gl.CopyImageSubData(src, st, a[0], a[1], a[2], a[3], dst, dt, b[0], b[1], b[2], b[3], w, h, d);
        break;
      }
      case Op::MemoryBarrier: gl.MemoryBarrier(r.get<GLbitfield>()); break;
      case Op::ProvokingVertex: gl.ProvokingVertex(r.get<GLenum>()); break;
      default: throw std::runtime_error("GL trace holds an unknown call (" + std::to_string(code) + ")");
    }
    const GLenum error = gl.GetError();
    if (error != GL_NO_ERROR)
      throw std::runtime_error("GL error " + std::to_string(error) + " replaying call " + std::to_string(r.calls) +
                               " (op " + std::to_string(code) + ")");
  }
  return r.calls;
}

GlFunctions substitutingFunctions(const GlFunctions& driver, std::istream& readbacks) {
  static Substitute substitute;
  substitute.driver = driver;
  substitute.readbacks = &readbacks;
  gSubstitute = &substitute;
  GlFunctions f = driver;
  f.ReadPixels = SubstitutedReadPixels;
  return f;
}

}  // namespace oitref::glcheck
