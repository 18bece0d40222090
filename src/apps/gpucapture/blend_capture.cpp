#include "gpucapture/blend_capture.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

#include "glcheck/gl_context.h"

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

struct Objects {
  const GlFunctions& gl;
  GLuint program = 0, vao = 0, buffer = 0, texture = 0, framebuffer = 0;
  explicit Objects(const GlFunctions& g) : gl(g) {}
  ~Objects() {
    gl.DeleteFramebuffers(1, &framebuffer);
    gl.DeleteTextures(1, &texture);
    gl.DeleteBuffers(1, &buffer);
    gl.DeleteVertexArrays(1, &vao);
    gl.DeleteProgram(program);
  }
};

void check(const GlFunctions& gl, const char* what) {
  const GLenum e = gl.GetError();
  if (e != GL_NO_ERROR) throw std::runtime_error(std::string(what) + " (GL error " + std::to_string(e) + ")");
}

// Blend state and constant as integers (the constant's bits: a NaN constant must sort too).
std::array<uint32_t, 10> stateKey(const GlBlendCase& c) {
  std::array<uint32_t, 10> k{c.equationRgb, c.equationAlpha, c.srcRgb, c.dstRgb, c.srcAlpha, c.dstAlpha};
  std::memcpy(&k[6], c.constant.data(), 16);
  return k;
}

// All cases of one format: `indices` into `cases`, results written to `out`.
void runFormat(Objects& o, const std::vector<GlBlendCase>& cases, std::vector<size_t> indices, std::vector<GlTexels>& out) {
  const GlFunctions& gl = o.gl;
  const GlTargetFormat f = cases[indices[0]].format;
  std::stable_sort(indices.begin(), indices.end(), [&](size_t a, size_t b) { return stateKey(cases[a]) < stateKey(cases[b]); });
  const int n = int(indices.size());
  const int height = (n + kWidth - 1) / kWidth;
  gl.DeleteFramebuffers(1, &o.framebuffer);
  gl.DeleteTextures(1, &o.texture);
  gl.GenTextures(1, &o.texture);
  gl.BindTexture(GL_TEXTURE_2D, o.texture);
  gl.TexStorage2D(GL_TEXTURE_2D, 1, f.internalFormat, kWidth, height);
  gl.GenFramebuffers(1, &o.framebuffer);
  gl.BindFramebuffer(GL_FRAMEBUFFER, o.framebuffer);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, o.texture, 0);
  const GLenum buffers[] = {GL_COLOR_ATTACHMENT0};
  gl.DrawBuffers(1, buffers);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("framebuffer of internal format " + std::to_string(f.internalFormat) + " is not complete");
  gl.Viewport(0, 0, kWidth, height);
  gl.Uniform1f(gl.GetUniformLocation(o.program, "height"), float(height));

  auto upload = [&](bool source) {
    std::vector<uint32_t> bits(size_t(kWidth) * size_t(height) * 4, 0);
    for (int i = 0; i < n; ++i) {
      const GlBlendCase& c = cases[indices[size_t(i)]];
      std::memcpy(&bits[size_t(i) * 4], (source ? c.source : c.destination).data(), 16);
    }
    gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, o.buffer);
    gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bits.size() * 4), bits.data(), GL_STATIC_DRAW);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, o.buffer);
  };
  auto readBack = [&] {
    std::vector<uint8_t> texels(size_t(kWidth) * size_t(height) * size_t(f.texelBytes));
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, kWidth, height, f.readFormat, f.readType, texels.data());
    return texels;
  };
  // 1. Destinations, blending off: what the format stores for them.
  gl.Disablei(GL_BLEND, 0);
  gl.ColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  upload(false);
  gl.DrawArrays(GL_POINTS, 0, n);
  const std::vector<uint8_t> stored = readBack();
  // 2. Sources, blended: one draw per run of equal blend state and constant.
  upload(true);
  gl.Enablei(GL_BLEND, 0);
  for (int first = 0; first < n;) {
    const GlBlendCase& c = cases[indices[size_t(first)]];
    int last = first + 1;
    while (last < n && stateKey(cases[indices[size_t(last)]]) == stateKey(c)) ++last;
    gl.BlendEquationSeparatei(0, c.equationRgb, c.equationAlpha);
    gl.BlendFuncSeparatei(0, c.srcRgb, c.dstRgb, c.srcAlpha, c.dstAlpha);
    gl.BlendColor(c.constant[0], c.constant[1], c.constant[2], c.constant[3]);
    gl.DrawArrays(GL_POINTS, first, last - first);
    first = last;
  }
  const std::vector<uint8_t> blended = readBack();
  check(gl, "drawing the blend cases");
  const size_t bytes = size_t(f.texelBytes);
  for (int i = 0; i < n; ++i) {
    GlTexels& t = out[indices[size_t(i)]];
    std::memcpy(t.destination.data(), &stored[size_t(i) * bytes], bytes);
    std::memcpy(t.result.data(), &blended[size_t(i) * bytes], bytes);
  }
}

}  // namespace

std::vector<GlTexels> captureBlendCases(const GlFunctions& gl, const std::vector<GlBlendCase>& cases) {
  std::vector<GlTexels> out(cases.size());
  if (cases.empty()) return out;
  Objects o(gl);
  o.program = linkProgram(gl, kVertexShader, kFragmentShader);
  gl.GenVertexArrays(1, &o.vao);
  gl.GenBuffers(1, &o.buffer);
  gl.Disable(GL_DITHER);  // on by default in GL (§17.3.8); a reference has none
  gl.Disable(GL_DEPTH_TEST);
  gl.Disable(GL_FRAMEBUFFER_SRGB);
  gl.UseProgram(o.program);
  gl.BindVertexArray(o.vao);
  std::map<GLenum, std::vector<size_t>> byFormat;
  for (size_t i = 0; i < cases.size(); ++i) byFormat[cases[i].format.internalFormat].push_back(i);
  for (const auto& [format, indices] : byFormat) runFormat(o, cases, indices, out);
  return out;
}

}  // namespace oitref::glcheck
