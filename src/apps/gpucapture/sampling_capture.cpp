#include "gpucapture/sampling_capture.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "glcheck/gl_context.h"

namespace oitref::glcheck {
namespace {

constexpr int kSamples = 4096;  // per experiment: the pixels of a 4096 × 1 RGBA32F target

const char* kVertexShader = R"(#version 430 core
void main() {  // one triangle over the viewport
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
})";

// Pixel i = gl_FragCoord.x − ½ (exact). Every coordinate below is a dyadic fraction that fp32
// holds exactly.
const char* kFragmentShader = R"(#version 430 core
uniform sampler2D tex;
uniform int experiment;
layout(location = 0) out vec4 colour;
vec2 bilinear(float i) {  // u − ½ = α, v − ½ = β on a 2×2 texture, every value dyadic
  return vec2((0.5 + mod(i, 64.0) / 64.0 + 3.0 / 1024.0) / 2.0, (0.5 + floor(i / 64.0) / 64.0 + 5.0 / 1024.0) / 2.0);
}
void main() {
  float i = gl_FragCoord.x - 0.5;
  if (experiment == 0) {         // LINEAR weight: u = 0.5 + i/4096 on a 2-texel row, α = u − ½
    colour = texture(tex, vec2((0.5 + i / 4096.0) / 2.0, 0.5));
  } else if (experiment == 1) {  // mipmap fraction: textureLod at λ = i/4096 between levels 0 and 1
    colour = textureLod(tex, vec2(0.5), i / 4096.0);
  } else if (experiment == 2) {  // implicit λ: block b = ⌊i/16⌋ has u = 2s = x·(1 + b/256), t constant: ρ = 1 + b/256
    float scale = 1.0 + floor(i / 16.0) / 256.0;
    colour = texture(tex, vec2(gl_FragCoord.x * scale / 2.0, 0.5));
  } else if (experiment == 3) {  // NEAREST edge: u = 1 + (i − 2048)/2^20 on a 2-texel row
    colour = texture(tex, vec2((1.0 + (i - 2048.0) / 1048576.0) / 2.0, 0.5));
  } else if (experiment == 4) {  // bilinear on 2×2: α = (i mod 64)/64 + 3/1024, β = ⌊i/64⌋/64 + 5/1024
    colour = texture(tex, bilinear(i));
  } else if (experiment == 5) {  // trilinear: α as above, β = 5/1024, textureLod at λ = ⌊i/64⌋/64
    colour = textureLod(tex, vec2(bilinear(i).x, (0.5 + 5.0 / 1024.0) / 2.0), floor(i / 64.0) / 64.0);
  } else if (experiment == 6) {  // sRGB decode: texel k = i mod 256 of a 256-texel row, NEAREST
    colour = texture(tex, vec2((mod(i, 256.0) + 0.5) / 256.0, 0.5));
  } else if (experiment == 7) {  // sRGB LINEAR between codes k = ⌊i/16⌋ and k + 1: u = k + ½ + (i mod 16)/16
    colour = texture(tex, vec2((floor(i / 16.0) + 0.5 + mod(i, 16.0) / 16.0) / 256.0, 0.5));
  } else {                       // magnification switch: α = ¼ on a 2×2 level, textureLod at λ = (i − 2048)/2048
    colour = textureLod(tex, vec2(0.375, 0.5), (i - 2048.0) / 2048.0);
  }
})";

void check(const GlFunctions& gl, const char* what) {
  const GLenum e = gl.GetError();
  if (e != GL_NO_ERROR) throw std::runtime_error(std::string("sampling capture: ") + what + " (GL error " + std::to_string(e) + ")");
}

// A texture whose level 0 is w × h of `level0` and, for `mipmapped`, level 1 (1 × 1) of
// `level1`; every channel of a texel the same byte.
GLuint makeTexture(const GlFunctions& gl, int w, int h, const std::vector<uint8_t>& level0, bool mipmapped, uint8_t level1,
                   GLenum minFilter, GLenum magFilter, GLenum format = GL_RGBA8) {
  GLuint t = 0;
  gl.GenTextures(1, &t);
  gl.BindTexture(GL_TEXTURE_2D, t);
  gl.TexStorage2D(GL_TEXTURE_2D, mipmapped ? 2 : 1, format, w, h);
  std::vector<uint8_t> rgba;
  for (uint8_t v : level0) rgba.insert(rgba.end(), {v, v, v, v});
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  if (mipmapped) {
    const uint8_t one[4] = {level1, level1, level1, level1};
    gl.TexSubImage2D(GL_TEXTURE_2D, 1, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, one);
  }
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GLint(minFilter));
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GLint(magFilter));
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  check(gl, "texture");
  return t;
}

}  // namespace

void captureSampling(const GlFunctions& gl, std::ostream& csv) {
  const GLuint program = linkProgram(gl, kVertexShader, kFragmentShader);
  GLuint vao = 0, target = 0, framebuffer = 0;
  gl.GenVertexArrays(1, &vao);
  gl.BindVertexArray(vao);
  gl.GenTextures(1, &target);
  gl.BindTexture(GL_TEXTURE_2D, target);
  gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, kSamples, 1);
  gl.GenFramebuffers(1, &framebuffer);
  gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) throw std::runtime_error("sampling capture: framebuffer incomplete");
  gl.UseProgram(program);
  gl.Uniform1i(gl.GetUniformLocation(program, "tex"), 0);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.Viewport(0, 0, kSamples, 1);
  check(gl, "set-up");

  struct Experiment {
    const char* name;
    GLuint texture;
  };
  std::vector<uint8_t> codes(256);
  for (int k = 0; k < 256; ++k) codes[size_t(k)] = uint8_t(k);
  const Experiment experiments[] = {
      {"linear_weight", makeTexture(gl, 2, 1, {0, 255}, false, 0, GL_LINEAR, GL_LINEAR)},
      {"mipmap_fraction", makeTexture(gl, 2, 2, {0, 0, 0, 0}, true, 255, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR)},
      {"implicit_lod", makeTexture(gl, 2, 2, {0, 0, 0, 0}, true, 255, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR)},
      {"nearest_edge", makeTexture(gl, 2, 1, {0, 255}, false, 0, GL_NEAREST, GL_NEAREST)},
      {"bilinear", makeTexture(gl, 2, 2, {10, 200, 90, 255}, false, 0, GL_LINEAR, GL_LINEAR)},
      {"trilinear", makeTexture(gl, 2, 2, {10, 200, 90, 255}, true, 77, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR)},
      {"srgb_decode", makeTexture(gl, 256, 1, codes, false, 0, GL_NEAREST, GL_NEAREST, GL_SRGB8_ALPHA8)},
      {"srgb_linear", makeTexture(gl, 256, 1, codes, false, 0, GL_LINEAR, GL_LINEAR, GL_SRGB8_ALPHA8)},
      {"magnification_switch", makeTexture(gl, 2, 2, {0, 255, 0, 255}, true, 128, GL_NEAREST_MIPMAP_NEAREST, GL_LINEAR)},
  };
  constexpr int kExperiments = int(std::size(experiments));
  csv << "experiment,index,exact,gpu,gpu_bits\n";
  std::vector<float> pixels(size_t(kSamples) * 4);
  for (int e = 0; e < kExperiments; ++e) {
    const Experiment& x = experiments[e];
    gl.BindTexture(GL_TEXTURE_2D, x.texture);
    gl.Uniform1i(gl.GetUniformLocation(program, "experiment"), e);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl.ReadPixels(0, 0, kSamples, 1, GL_RGBA, GL_FLOAT, pixels.data());
    check(gl, x.name);
    // The implicit experiment keeps one pixel per 16-pixel block (s is affine in x within one,
    // and blocks hold whole quads).
    const int first = e == 2 ? 8 : 0, step = e == 2 ? 16 : 1;
    for (int i = first; i < kSamples; i += step) {
        // srgb_decode's second half records alpha (linear in an sRGB texture), the rest red.
        const int channel = e == 6 && i >= 2048 ? 3 : 0;
        const float v = pixels[size_t(i) * 4 + size_t(channel)];
        uint32_t bits;
        std::memcpy(&bits, &v, 4);
        double exact = 0;
        // `exact`: what the exact rule gives, or for the later experiments the parameter swept.
        switch (e) {
          case 0: exact = i / 4096.0; break;                          // α
          case 1: exact = i / 4096.0; break;                          // frac λ
          case 2: exact = std::log2(1.0 + (i / 16) / 256.0); break;  // λ = log2 ρ
          case 3: exact = i >= 2048 ? 1.0 : 0.0; break;              // texel 1 from u ≥ 1
          case 4: case 5: exact = (i % 64) / 64.0 + 3.0 / 1024.0; break;  // α
          case 6: exact = (i % 256) / 255.0; break;                  // the code as UNORM
          case 7: exact = (i % 16) / 16.0; break;                    // α
          default: exact = (i - 2048) / 2048.0; break;               // λ
        }
        char line[160];
        std::snprintf(line, sizeof line, "%s,%d,%.9g,%.9g,%08x\n", x.name, i, exact, double(v), bits);
        csv << line;
    }
  }
  for (const Experiment& x : experiments) gl.DeleteTextures(1, &x.texture);
  gl.DeleteFramebuffers(1, &framebuffer);
  gl.DeleteTextures(1, &target);
  gl.DeleteVertexArrays(1, &vao);
  gl.DeleteProgram(program);
}

}  // namespace oitref::glcheck
