#include "glcheck/blend_check.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <numeric>
#include <ostream>
#include <stdexcept>

#include "glcheck/gl_format.h"
#include "glcheck/gl_state.h"

namespace oitref::glcheck {
namespace {

constexpr int kWidth = 256;  // a power of two: texel centres are exact in NDC

// Point i sits at the centre of texel (i mod W, i div W); size 1, so it covers only that texel.
const char* kVertexShader = R"(#version 430 core
uniform float height;
void main() {
  int x = gl_VertexID % 256, y = gl_VertexID / 256;
  gl_Position = vec4((2.0 * float(x) + 1.0) / 256.0 - 1.0, (2.0 * float(y) + 1.0) / height - 1.0, 0.0, 1.0);
})";

// The colour is the case's value, bit for bit.
const char* kFragmentShader = R"(#version 430 core
layout(std430, binding = 0) readonly buffer Values { uvec4 v[]; };
layout(location = 0) out vec4 colour;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  colour = uintBitsToFloat(v[p.y * 256 + p.x]);
})";

struct GlObjects {
  const GlFunctions& gl;
  GLuint program = 0, vao = 0, buffer = 0;
  explicit GlObjects(const GlFunctions& g) : gl(g) {}
  ~GlObjects() {
    gl.DeleteBuffers(1, &buffer);
    gl.DeleteVertexArrays(1, &vao);
    gl.DeleteProgram(program);
  }
};

struct Target {
  const GlFunctions& gl;
  GLuint texture = 0, framebuffer = 0;
  Target(const GlFunctions& g, const GlFormat& f, int height) : gl(g) {
    gl.GenTextures(1, &texture);
    gl.BindTexture(GL_TEXTURE_2D, texture);
    gl.TexStorage2D(GL_TEXTURE_2D, 1, f.internalFormat, kWidth, height);
    gl.GenFramebuffers(1, &framebuffer);
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0};
    gl.DrawBuffers(1, buffers);
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("framebuffer with the format is not complete");
  }
  ~Target() {
    gl.DeleteFramebuffers(1, &framebuffer);
    gl.DeleteTextures(1, &texture);
  }
};

void upload(const GlFunctions& gl, GLuint buffer, const std::vector<uint32_t>& bits) {
  gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
  gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bits.size() * 4), bits.data(), GL_STATIC_DRAW);
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
}

std::vector<uint8_t> readBack(const GlFunctions& gl, const GlFormat& f, int height, int texelBytes) {
  std::vector<uint8_t> texels(size_t(kWidth) * size_t(height) * size_t(texelBytes));
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.ReadPixels(0, 0, kWidth, height, f.readFormat, f.readType, texels.data());
  return texels;
}

void setBlend(const GlFunctions& gl, const tools::BlendCase& c) {
  BlendState state = c.state;
  state.enabled = true;
  applyBlendState(gl, 0, state);
  gl.BlendColor(c.constant.r, c.constant.g, c.constant.b, c.constant.a);
}

bool sameGroup(const tools::BlendCase& a, const tools::BlendCase& b) {
  return a.state == b.state && std::memcmp(&a.constant, &b.constant, sizeof a.constant) == 0;
}

// All cases of one format: `indices` into `cases`, results written to `out`.
void runFormat(const GlContext& context, const std::vector<tools::BlendCase>& cases, std::vector<size_t> indices,
               const GlObjects& objects, std::vector<GlTexels>& out) {
  const GlFunctions& gl = context.gl();
  const Format format = cases[indices[0]].format;
  const auto glFormat = glFormatOf(format);
  if (!glFormat) throw std::invalid_argument("format " + format.name() + " has no OpenGL equivalent");
  // Cases of a group are drawn together; the order inside a texel does not matter (one case each).
  std::stable_sort(indices.begin(), indices.end(), [&](size_t a, size_t b) {
    const auto& x = cases[a];
    const auto& y = cases[b];
    if (!(x.state == y.state)) return x.state.describe() < y.state.describe();
    return std::memcmp(&x.constant, &y.constant, sizeof x.constant) < 0;
  });
  const int n = int(indices.size());
  const int height = (n + kWidth - 1) / kWidth;
  Target target(gl, *glFormat, height);
  gl.Viewport(0, 0, kWidth, height);
  gl.UseProgram(objects.program);
  gl.Uniform1f(gl.GetUniformLocation(objects.program, "height"), float(height));
  gl.BindVertexArray(objects.vao);

  auto bitsOf = [&](auto member) {
    std::vector<uint32_t> bits(size_t(kWidth) * size_t(height) * 4, 0);
    for (int i = 0; i < n; ++i) std::memcpy(&bits[size_t(i) * 4], &(cases[indices[size_t(i)]].*member), 16);
    return bits;
  };
  // 1. Destinations, blending off: what the format stores for them.
  applyBlendState(gl, 0, BlendState::disabled());
  upload(gl, objects.buffer, bitsOf(&tools::BlendCase::destination));
  gl.DrawArrays(GL_POINTS, 0, n);
  const std::vector<uint8_t> stored = readBack(gl, *glFormat, height, format.bytesPerTexel());
  // 2. Sources, blended: one draw per run of equal blend state and constant.
  upload(gl, objects.buffer, bitsOf(&tools::BlendCase::source));
  for (int first = 0; first < n;) {
    int last = first + 1;
    while (last < n && sameGroup(cases[indices[size_t(first)]], cases[indices[size_t(last)]])) ++last;
    setBlend(gl, cases[indices[size_t(first)]]);
    gl.DrawArrays(GL_POINTS, first, last - first);
    first = last;
  }
  const std::vector<uint8_t> blended = readBack(gl, *glFormat, height, format.bytesPerTexel());
  context.check(("drawing the " + format.name() + " cases").c_str());
  const size_t bytes = size_t(format.bytesPerTexel());
  for (int i = 0; i < n; ++i) {
    GlTexels& t = out[indices[size_t(i)]];
    std::memcpy(t.destination.data(), &stored[size_t(i) * bytes], bytes);
    std::memcpy(t.result.data(), &blended[size_t(i) * bytes], bytes);
  }
}

}  // namespace

std::vector<GlTexels> runBlendCases(const GlContext& context, const std::vector<tools::BlendCase>& cases) {
  const GlFunctions& gl = context.gl();
  GlObjects objects(gl);
  objects.program = linkProgram(gl, kVertexShader, kFragmentShader);
  gl.GenVertexArrays(1, &objects.vao);
  gl.GenBuffers(1, &objects.buffer);
  gl.Disable(GL_DITHER);  // on by default in GL (§17.3.8); a reference has none
  gl.Disable(GL_DEPTH_TEST);
  gl.Disable(GL_FRAMEBUFFER_SRGB);
  std::map<std::string, std::vector<size_t>> byFormat;
  for (size_t i = 0; i < cases.size(); ++i) byFormat[cases[i].format.name()].push_back(i);
  std::vector<GlTexels> out(cases.size());
  for (const auto& [name, indices] : byFormat) runFormat(context, cases, indices, objects, out);
  return out;
}

}  // namespace oitref::glcheck
