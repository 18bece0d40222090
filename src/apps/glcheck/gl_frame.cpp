#include "glcheck/gl_frame.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "glcheck/gl_format.h"
#include "glcheck/gl_state.h"
#include "methods/method_common.h"

namespace oitref::glcheck {
namespace {

// Clip position, colour and quad uv, passed through (the vertex stage already ran in oitref).
const char* kSceneVertexShader = R"(#version 430 core
layout(location = 0) in vec4 clipPosition;
layout(location = 1) in vec4 colour;
layout(location = 2) in vec2 uv;
out vec4 vColour;
out vec2 vUv;
void main() {
  gl_Position = clipPosition;
  vColour = colour;
  vUv = uv;
})";

// One triangle over the whole viewport (drawFullscreen).
const char* kFullscreenVertexShader = R"(#version 430 core
out vec4 vColour;
out vec2 vUv;
void main() {
  gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0);
  vColour = vec4(0.0);
  vUv = vec2(0.0);
})";

// Mirrors oitref::shadeSurface (scene_geometry.cpp), methods/power.h and FragmentInput's depths
// (viewDepth is clip w: 1 / gl_FragCoord.w).
const char* kFragmentPrelude = R"(
in vec4 vColour;
in vec2 vUv;
uniform bool particles, textured;
uniform float alphaTest;  // < 0: none
uniform sampler2D surfaceTexture;
vec4 shadeSurface() {
  vec4 c = vColour;
  if (particles) {
    float x = 2.0 * vUv.x - 1.0, y = 2.0 * vUv.y - 1.0;
    float r2 = x * x + y * y;
    c.a = c.a * (r2 < 1.0 ? (1.0 - r2) * (1.0 - r2) : 0.0);
  }
  if (textured) c = c * texture(surfaceTexture, vUv);
  if (alphaTest >= 0.0 && !(c.a >= alphaTest)) discard;
  return c;
}
float powInt(float x, uint n) {
  float r = 1.0;
  while (n != 0u) {
    if ((n & 1u) != 0u) r *= x;
    x *= x;
    n >>= 1u;
  }
  return r;
}
vec4 fetch(sampler2D s) { return texelFetch(s, ivec2(gl_FragCoord.xy), 0); }
float windowDepth() { return gl_FragCoord.z; }
float viewDepth() { return 1.0 / gl_FragCoord.w; }
)";

GLenum depthInternalFormat(DepthFormat f) {
  switch (f) {
    case DepthFormat::D16: return GL_DEPTH_COMPONENT16;
    case DepthFormat::D24: return GL_DEPTH_COMPONENT24;
    case DepthFormat::D32F: return GL_DEPTH_COMPONENT32F;
  }
  return GL_DEPTH_COMPONENT24;
}

}  // namespace

std::string glslFloat(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, 4);
  char text[40];
  std::snprintf(text, sizeof text, "uintBitsToFloat(0x%08xu)", bits);
  return text;
}

GlFrame::GlFrame(const GlContext& context, const FrameContext& frame, const std::vector<AttachmentDecl>& attachments)
    : context_(context), gl_(context.gl()), frame_(frame) {
  std::vector<AttachmentDecl> all = attachments;
  AttachmentDecl analysis;
  analysis.name = "analysis";
  analysis.format = parseFormat("rgba32f");
  analysis.purpose = "oitref's RGBA32F analysis copy";
  all.push_back(analysis);
  for (const AttachmentDecl& a : all) {
    Texture t;
    t.isDepth = a.isDepth;
    t.format = a.format;
    GLenum internal = depthInternalFormat(a.depthFormat);
    if (!a.isDepth) {
      const auto f = glFormatOf(a.format);
      if (!f) throw std::invalid_argument("attachment '" + a.name + "': format " + a.format.name() + " has no OpenGL equivalent");
      internal = f->internalFormat;
    }
    gl_.GenTextures(1, &t.id);
    gl_.BindTexture(GL_TEXTURE_2D, t.id);
    gl_.TexStorage2D(GL_TEXTURE_2D, 1, internal, frame.width, frame.height);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    textures_[a.name] = t;
  }
  const glm::mat4 vp = frame.viewProjection();
  for (const ScenePart& sp : frame.geometry.parts) {
    const Geometry g = toClipGeometry(sp, vp);
    std::vector<float> interleaved;
    interleaved.reserve(g.vertexCount() * 10);
    for (size_t v = 0; v < g.vertexCount(); ++v) {
      for (int k = 0; k < 4; ++k) interleaved.push_back(g.clipPositions[v][k]);
      const float* a = g.vertexAttributes(uint32_t(v));
      interleaved.insert(interleaved.end(), a, a + kSceneAttributeCount);
    }
    Part p;
    p.transparent = sp.transparent;
    const SceneObject& object = frame.scene.objects[sp.objectIndex];
    p.particles = object.type == ObjectType::Particles;
    if (object.texture) p.texture = uploadTexture(object);
    if (object.alphaTest) p.alphaTest = *object.alphaTest;
    p.objectIndex = int(sp.objectIndex);
    p.index = int(parts_.size());
    p.indexCount = GLsizei(g.indices.size());
    gl_.GenVertexArrays(1, &p.vao);
    gl_.BindVertexArray(p.vao);
    gl_.GenBuffers(1, &p.vertices);
    gl_.BindBuffer(GL_ARRAY_BUFFER, p.vertices);
    gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(interleaved.size() * 4), interleaved.data(), GL_STATIC_DRAW);
    const GLsizei stride = 10 * 4;
    gl_.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(0));
    gl_.VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(16));
    gl_.VertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(32));
    for (GLuint i = 0; i < 3; ++i) gl_.EnableVertexAttribArray(i);
    gl_.GenBuffers(1, &p.indices);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, p.indices);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(g.indices.size() * 4), g.indices.data(), GL_STATIC_DRAW);
    parts_.push_back(p);
  }
  gl_.GenVertexArrays(1, &emptyVao_);
  gl_.BindVertexArray(0);
  gl_.Disable(GL_DITHER);  // on by default in GL (§17.3.8); oitref has none
  gl_.Disable(GL_FRAMEBUFFER_SRGB);
  gl_.Disable(GL_CULL_FACE);
  gl_.Viewport(0, 0, frame.width, frame.height);
  // GL leaves a new texture's contents undefined; a driver may hand back memory another frame
  // used. Every attachment starts cleared (colour 0, depth 1), so that no read of one a method has
  // not written yet can depend on what ran before in the same context.
  for (const AttachmentDecl& a : all) {
    if (a.isDepth) clearDepth(a.name, 1.0f);
    else clear(a.name, glm::vec4(0.0f));
  }
  context_.check("setting up the frame");
}

GlFrame::~GlFrame() {
  if (!queries_.empty()) gl_.DeleteQueries(GLsizei(queries_.size()), queries_.data());
  for (auto& [key, fb] : framebuffers_) gl_.DeleteFramebuffers(1, &fb);
  for (auto& [key, p] : programs_) gl_.DeleteProgram(p);
  for (auto& [name, t] : textures_) gl_.DeleteTextures(1, &t.id);
  for (Part& p : parts_) {
    if (p.texture) gl_.DeleteTextures(1, &p.texture);
    gl_.DeleteBuffers(1, &p.vertices);
    gl_.DeleteBuffers(1, &p.indices);
    gl_.DeleteVertexArrays(1, &p.vao);
  }
  gl_.DeleteVertexArrays(1, &emptyVao_);
  if (!storage_.empty()) gl_.DeleteBuffers(GLsizei(storage_.size()), storage_.data());
}

const GlFrame::Texture& GlFrame::texture(const std::string& name) const {
  const auto it = textures_.find(name);
  if (it == textures_.end()) throw std::logic_error("GL method uses undeclared attachment '" + name + "'");
  return it->second;
}

void GlFrame::bindTargets(const std::vector<std::string>& colours, const std::string& depth) {
  std::string key = depth;
  for (const std::string& c : colours) key += "|" + c;
  GLuint& fb = framebuffers_[key];
  if (fb == 0) {
    gl_.GenFramebuffers(1, &fb);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, fb);
    std::vector<GLenum> buffers;
    for (size_t i = 0; i < colours.size(); ++i) {
      const Texture& t = texture(colours[i]);
      if (t.isDepth) throw std::logic_error("'" + colours[i] + "' is a depth attachment");
      gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + i), GL_TEXTURE_2D, t.id, 0);
      buffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
    }
    if (!depth.empty()) gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, texture(depth).id, 0);
    if (buffers.empty()) gl_.DrawBuffers(0, nullptr);
    else gl_.DrawBuffers(GLsizei(buffers.size()), buffers.data());
    if (!colours.empty()) gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
    if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("framebuffer " + key + " is not complete");
  }
  gl_.BindFramebuffer(GL_FRAMEBUFFER, fb);
}

void GlFrame::clear(const std::string& colour, const glm::vec4& value) {
  bindTargets({colour}, "");
  applyBlendState(gl_, 0, BlendState::disabled());  // restores the colour mask
  gl_.ClearBufferfv(GL_COLOR, 0, &value[0]);
}

void GlFrame::clearDepth(const std::string& depth, float value) {
  bindTargets({}, depth);
  gl_.DepthMask(GL_TRUE);
  gl_.ClearBufferfv(GL_DEPTH, 0, &value);
}

void GlFrame::addScratch(const std::string& name, const std::string& like) {
  const Texture& model = texture(like);
  Texture t = model;
  GLint internal = 0;
  gl_.BindTexture(GL_TEXTURE_2D, model.id);
  gl_.GetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, &internal);
  gl_.GenTextures(1, &t.id);
  gl_.BindTexture(GL_TEXTURE_2D, t.id);
  gl_.TexStorage2D(GL_TEXTURE_2D, 1, GLenum(internal), frame_.width, frame_.height);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  textures_[name] = t;
}

void GlFrame::copy(const std::string& from, const std::string& to) {
  gl_.CopyImageSubData(texture(from).id, GL_TEXTURE_2D, 0, 0, 0, 0, texture(to).id, GL_TEXTURE_2D, 0, 0, 0, 0,
                       frame_.width, frame_.height, 1);
  context_.check(("copying " + from + " to " + to).c_str());
}

Image GlFrame::read(const std::string& colour) {
  const Texture& t = texture(colour);
  const auto f = glFormatOf(t.format);
  Image image(t.format, frame_.width, frame_.height);
  bindTargets({colour}, "");
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl_.ReadPixels(0, 0, frame_.width, frame_.height, f->readFormat, f->readType, image.texel(0, 0));
  context_.check(("reading " + colour).c_str());
  return image;
}

GLuint GlFrame::program(const std::string& vertex, const std::string& main, size_t colourCount,
                        const std::vector<GlInput>& inputs) {
  std::string source = "#version 430 core\n";
  // A pass's own #extension lines (at the start of `main`) go before any declaration.
  std::string body = main;
  while (body.rfind("#extension", 0) == 0) {
    const size_t end = body.find('\n');
    source += body.substr(0, end + 1);
    body = end == std::string::npos ? std::string() : body.substr(end + 1);
  }
  for (size_t i = 0; i < colourCount; ++i)
    source += "layout(location = " + std::to_string(i) + ") out vec4 o" + std::to_string(i) + ";\n";
  for (const GlInput& in : inputs) source += "uniform sampler2D " + in.sampler + ";\n";
  source += kFragmentPrelude;
  source += body;
  GLuint& p = programs_[vertex + source];
  if (p == 0) p = linkProgram(gl_, vertex, source);
  gl_.UseProgram(p);
  return p;
}

// The unit of an object's texture: above those of a pass's inputs.
constexpr GLenum kSurfaceTextureUnit = 15;

void GlFrame::bindInputs(GLuint program, const std::vector<GlInput>& inputs) {
  if (inputs.size() >= kSurfaceTextureUnit)
    throw std::invalid_argument("a pass reads " + std::to_string(inputs.size()) +
                                " attachments; the GL frame binds at most " + std::to_string(kSurfaceTextureUnit - 1) +
                                " beside the object's texture (stochastic: samples=8)");
  for (size_t i = 0; i < inputs.size(); ++i) {
    gl_.ActiveTexture(GLenum(GL_TEXTURE0 + i));
    gl_.BindTexture(GL_TEXTURE_2D, texture(inputs[i].attachment).id);
    gl_.Uniform1i(gl_.GetUniformLocation(program, inputs[i].sampler.c_str()), GLint(i));
  }
}

GLuint GlFrame::uploadTexture(const SceneObject& object) {
  const Texture2D& t = *object.texture;
  const SamplerState& sp = object.sampler;
  if (sp.lodBias != 0.0f || sp.minLod != -1000.0f || sp.maxLod != 1000.0f)
    throw std::invalid_argument("glcheck scene: object texture '" + object.textureFile +
                                "' has a LOD bias or range, which the GL frame does not set");
  auto filter = [](TextureFilter f) -> GLint {
    constexpr GLint gl[] = {GL_NEAREST, GL_LINEAR, GL_NEAREST_MIPMAP_NEAREST, GL_LINEAR_MIPMAP_NEAREST,
                            GL_NEAREST_MIPMAP_LINEAR, GL_LINEAR_MIPMAP_LINEAR};
    return gl[size_t(f)];
  };
  auto wrap = [](WrapMode m) -> GLint {
    return m == WrapMode::Repeat ? GL_REPEAT : m == WrapMode::ClampToEdge ? GL_CLAMP_TO_EDGE : GL_MIRRORED_REPEAT;
  };
  GLuint id = 0;
  gl_.GenTextures(1, &id);
  gl_.ActiveTexture(GL_TEXTURE0 + kSurfaceTextureUnit);
  gl_.BindTexture(GL_TEXTURE_2D, id);
  gl_.TexStorage2D(GL_TEXTURE_2D, t.levels(), t.format() == TextureFormat::Srgb8Alpha8 ? GL_SRGB8_ALPHA8 : GL_RGBA8,
                   t.level(0).width, t.level(0).height);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 4);  // rows of RGBA8 texels are whole words
  for (int i = 0; i < t.levels(); ++i)
    gl_.TexSubImage2D(GL_TEXTURE_2D, i, 0, 0, t.level(i).width, t.level(i).height, GL_RGBA, GL_UNSIGNED_BYTE,
                      t.level(i).texels.data());
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter(sp.minFilter));
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter(sp.magFilter));
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap(sp.wrapS));
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap(sp.wrapT));
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, t.levels() - 1);
  gl_.ActiveTexture(GL_TEXTURE0);
  context_.check("object texture");
  return id;
}

GlFrame::PartUniforms GlFrame::partUniforms(GLuint program) {
  gl_.Uniform1i(gl_.GetUniformLocation(program, "surfaceTexture"), GLint(kSurfaceTextureUnit));
  return {gl_.GetUniformLocation(program, "particles"), gl_.GetUniformLocation(program, "textured"),
          gl_.GetUniformLocation(program, "alphaTest"), gl_.GetUniformLocation(program, "objectIndex"),
          gl_.GetUniformLocation(program, "partIndex")};
}

void GlFrame::usePart(const PartUniforms& u, const Part& p) {
  gl_.Uniform1i(u.particles, p.particles ? 1 : 0);
  gl_.Uniform1i(u.textured, p.texture ? 1 : 0);
  gl_.Uniform1f(u.alphaTest, p.alphaTest);
  if (u.objectIndex >= 0) gl_.Uniform1i(u.objectIndex, p.objectIndex);
  if (u.partIndex >= 0) gl_.Uniform1i(u.partIndex, p.index);
  if (p.texture) {
    gl_.ActiveTexture(GL_TEXTURE0 + kSurfaceTextureUnit);
    gl_.BindTexture(GL_TEXTURE_2D, p.texture);
    gl_.ActiveTexture(GL_TEXTURE0);
  }
  gl_.BindVertexArray(p.vao);
}

void GlFrame::drawParts(GLuint program, bool transparent, bool everything) {
  const PartUniforms uniforms = partUniforms(program);
  for (const Part& p : parts_) {
    if (p.transparent != transparent && !everything) continue;
    usePart(uniforms, p);
    gl_.DrawElements(GL_TRIANGLES, p.indexCount, GL_UNSIGNED_INT, nullptr);
  }
  gl_.BindVertexArray(0);
}

void GlFrame::transparentPassInOrder(const std::vector<std::pair<size_t, size_t>>& triangles, const std::string& main,
                                     const std::vector<std::string>& colours, const std::string& depth,
                                     const PipelineState& state) {
  const PassQuery timed(*this, "transparent");
  // Each part's triangles in the sequence's order, as an index buffer of its own: a run of the
  // sequence in one part is then a range of that buffer.
  std::vector<std::vector<uint32_t>> ordered(parts_.size());
  struct Run {
    size_t part;
    size_t first, count;  // in triangles, of ordered[part]
  };
  std::vector<Run> runs;
  for (const auto& [part, triangle] : triangles) {
    const std::vector<uint32_t>& indices = frame_.geometry.parts.at(part).indices;
    if (runs.empty() || runs.back().part != part) runs.push_back({part, ordered[part].size() / 3, 0});
    ++runs.back().count;
    ordered[part].insert(ordered[part].end(), indices.begin() + std::ptrdiff_t(3 * triangle),
                         indices.begin() + std::ptrdiff_t(3 * triangle + 3));
  }
  std::vector<GLuint> buffers(parts_.size(), 0);
  for (size_t p = 0; p < parts_.size(); ++p) {
    if (ordered[p].empty()) continue;
    gl_.BindVertexArray(parts_[p].vao);
    gl_.GenBuffers(1, &buffers[p]);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[p]);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(ordered[p].size() * 4), ordered[p].data(), GL_STATIC_DRAW);
  }
  bindTargets(colours, depth);
  applyPipelineState(gl_, state, int(colours.size()));
  const PartUniforms uniforms = partUniforms(this->program(kSceneVertexShader, main, colours.size(), {}));
  for (const Run& r : runs) {
    usePart(uniforms, parts_[r.part]);
    gl_.DrawElements(GL_TRIANGLES, GLsizei(3 * r.count), GL_UNSIGNED_INT, reinterpret_cast<const void*>(12 * r.first));
  }
  for (size_t p = 0; p < parts_.size(); ++p) {  // each part's own indices again
    if (!buffers[p]) continue;
    gl_.BindVertexArray(parts_[p].vao);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, parts_[p].indices);
    gl_.DeleteBuffers(1, &buffers[p]);
  }
  gl_.BindVertexArray(0);
  context_.check("transparent pass in order");
}

GlFrame::PassQuery::PassQuery(GlFrame& frame, const char* kind) : frame_(frame), active_(frame.timing_) {
  if (!active_) return;
  const size_t i = frame_.queryKinds_.size();
  if (i == frame_.queries_.size()) {
    GLuint q = 0;
    frame_.gl_.GenQueries(1, &q);
    frame_.queries_.push_back(q);
  }
  frame_.queryKinds_.push_back(kind);
  frame_.gl_.BeginQuery(GL_TIME_ELAPSED, frame_.queries_[i]);
}

GlFrame::PassQuery::~PassQuery() {
  if (active_) frame_.gl_.EndQuery(GL_TIME_ELAPSED);
}

std::vector<std::pair<std::string, double>> GlFrame::takePassTimes() {
  std::vector<std::pair<std::string, double>> times;
  for (size_t i = 0; i < queryKinds_.size(); ++i) {
    GLuint64 ns = 0;
    gl_.GetQueryObjectui64v(queries_[i], GL_QUERY_RESULT, &ns);
    times.emplace_back(queryKinds_[i], double(ns) * 1e-6);
  }
  queryKinds_.clear();
  context_.check("timer queries");
  return times;
}

void GlFrame::opaquePass(bool everything) {
  const PassQuery timed(*this, "opaque");
  const glm::vec4 background(frame_.scene.background, 1.0f);
  clear("opaque", background);
  clear("analysis", background);
  clearDepth("depth", 1.0f);
  PipelineState st;
  st.depth = {true, CompareFunc::Less, true, false};
  bindTargets({"opaque", "analysis"}, "depth");
  applyPipelineState(gl_, st, 2);
  const GLuint p = program(kSceneVertexShader, R"(
void main() {
  vec4 c = shadeSurface();
  o0 = vec4(c.rgb, 1.0);
  o1 = vec4(c.rgb, 1.0);
})", 2, {});
  drawParts(p, false, everything);
  context_.check("opaque pass");
}

void GlFrame::transparentPass(const std::string& main, const std::vector<std::string>& colours, const std::string& depth,
                              const PipelineState& state, const std::vector<GlInput>& inputs) {
  const PassQuery timed(*this, "transparent");
  bindTargets(colours, depth);
  applyPipelineState(gl_, state, int(colours.size()));
  const GLuint p = program(kSceneVertexShader, main, colours.size(), inputs);
  bindInputs(p, inputs);
  drawParts(p, true, false);
  context_.check("transparent pass");
}

void GlFrame::fullscreenPass(const std::string& main, const std::vector<std::string>& colours, const PipelineState& state,
                             const std::vector<GlInput>& inputs) {
  const PassQuery timed(*this, "full-screen");
  fullscreenDraw(main, colours, state, inputs);
}

void GlFrame::fullscreenDraw(const std::string& main, const std::vector<std::string>& colours, const PipelineState& state,
                             const std::vector<GlInput>& inputs) {
  bindTargets(colours, "");
  applyPipelineState(gl_, state, int(colours.size()));
  const GLuint p = program(kFullscreenVertexShader, main, colours.size(), inputs);
  bindInputs(p, inputs);
  gl_.Uniform1i(gl_.GetUniformLocation(p, "particles"), 0);
  gl_.Uniform1i(gl_.GetUniformLocation(p, "textured"), 0);
  gl_.Uniform1f(gl_.GetUniformLocation(p, "alphaTest"), -1.0f);
  gl_.BindVertexArray(emptyVao_);
  gl_.DrawArrays(GL_TRIANGLES, 0, 3);
  gl_.BindVertexArray(0);
  context_.check("full-screen pass");
}

void GlFrame::blendOverBackground(const std::string& main, const std::vector<GlInput>& inputs) {
  PipelineState composite;
  composite.blend[0] = composite.blend[1] = compositeBlend();
  const PassQuery timed(*this, "composite");
  fullscreenDraw(main, {"opaque", "analysis"}, composite, inputs);
}

void GlFrame::compositeOntoBackgrounds(const std::string& resolve, const std::vector<GlInput>& inputs) {
  for (const char* name : {"opaque", "analysis"}) {
    const std::string copy = std::string("background_") + name;
    if (!textures_.count(copy)) addScratch(copy, name);
    this->copy(name, copy);
  }
  std::vector<GlInput> all = inputs;
  all.push_back({"backgroundOpaque", "background_opaque"});
  all.push_back({"backgroundAnalysis", "background_analysis"});
  const PassQuery timed(*this, "composite");
  fullscreenDraw(resolve + R"(
void main() {
  vec3 r0, r1;
  if (!resolve(fetch(backgroundOpaque).rgb, fetch(backgroundAnalysis).rgb, r0, r1)) discard;
  o0 = vec4(r0, 1.0);
  o1 = vec4(r1, 1.0);
})",
                 {"opaque", "analysis"}, PipelineState{}, all);
}

void GlFrame::storageBuffer(GLuint binding, size_t bytes, const void* data) {
  GLuint b = 0;
  gl_.GenBuffers(1, &b);
  storage_.push_back(b);
  gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, b);
  gl_.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), data, GL_DYNAMIC_COPY);
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, b);
  context_.check("creating a shader storage buffer");
}

void GlFrame::storageBarrier() { gl_.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT); }

}  // namespace oitref::glcheck
