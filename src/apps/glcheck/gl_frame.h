// The GL side of one method's frame, mirroring methods/method_common.h: the method's declared
// attachments (plus oitref's RGBA32F analysis copy) as GL textures of the same formats, the
// scene's triangles, and the passes every method shares. A GL method (gl_methods.cpp) is then
// the C++ method's sequence of passes with GLSL in place of the lambdas.
//
// Geometry goes to GL in the clip space oitref's own vertex stage computes (toClipGeometry),
// with the six scene attributes, and the vertex shader passes them through: both pipelines
// rasterise the same fp32 clip positions. What can differ is what a driver does after that —
// snapping, interpolation, the shader arithmetic, conversions and blending — which is what
// scene mode measures.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "glcheck/gl_context.h"
#include "oitref/oit/method.h"
#include "oitref/core/pipeline_state.h"

namespace oitref::glcheck {

// A texture a pass reads with fetch(): the GLSL sampler name and the attachment bound to it.
struct GlInput {
  std::string sampler, attachment;
};

// An fp32 value as a GLSL expression with exactly its bits: "uintBitsToFloat(0x3f800000u)".
std::string glslFloat(float value);

class GlFrame {
 public:
  GlFrame(const GlContext& context, const FrameContext& frame, const std::vector<AttachmentDecl>& attachments);
  ~GlFrame();
  GlFrame(const GlFrame&) = delete;
  GlFrame& operator=(const GlFrame&) = delete;

  const FrameContext& context() const { return frame_; }

  void clear(const std::string& colour, const glm::vec4& value);
  void clearDepth(const std::string& depth, float value);
  void copy(const std::string& from, const std::string& to);  // glCopyImageSubData, equal formats
  // A texture of `like`'s format that no method declares: a pass that reads an attachment it
  // also renders to reads a copy instead (GL leaves such feedback loops undefined, §9.3.1).
  void addScratch(const std::string& name, const std::string& like);
  // A colour attachment read back in its own bits, as the emulated Image of the same format.
  Image read(const std::string& colour);

  // The passes. A pass's GLSL `main` follows the shared prelude, which declares
  //   out vec4 o0, o1, ...                  one per colour target, in order
  //   vec4 shadeSurface()                   the object's straight colour (oitref::shadeSurface)
  //   float windowDepth(), viewDepth()      FragmentInput's depth and viewDepth
  //   float powInt(float, uint)             methods/power.h
  //   vec4 fetch(sampler2D)                 texelFetch at this pixel
  // and the samplers named in `inputs`. A scene part's draws set `uniform int objectIndex` and
  // `uniform int partIndex` where `main` declares them.

  // "opaque" cleared to the background, "depth" to 1, the opaque objects (all with
  // `everything`) drawn with depth test LESS and writes: PassRunner::opaquePass.
  void opaquePass(bool everything = false);
  // The transparent objects in submission order: PassRunner::transparentPass.
  void transparentPass(const std::string& main, const std::vector<std::string>& colours, const std::string& depth,
                       const PipelineState& state, const std::vector<GlInput>& inputs = {});
  // transparentPass with the triangles in this order instead: (part, triangle) of
  // frame.geometry.parts, drawn as one draw per run of one part's triangles, which gives every
  // pixel the fragments in the sequence's order, as methods/sorted.cpp's single draw does.
  void transparentPassInOrder(const std::vector<std::pair<size_t, size_t>>& triangles, const std::string& main,
                              const std::vector<std::string>& colours, const std::string& depth, const PipelineState& state);
  void fullscreenPass(const std::string& main, const std::vector<std::string>& colours, const PipelineState& state,
                      const std::vector<GlInput>& inputs = {});
  // `main` writes the resolved (colour, T) to o0 and o1, or discards: PassRunner::blendOverBackground.
  void blendOverBackground(const std::string& main, const std::vector<GlInput>& inputs);
  // A shader storage buffer of `bytes` (its contents `data`, or undefined) at `binding`, kept
  // until the frame ends; storageBarrier makes a pass's writes to it visible to the next pass.
  void storageBuffer(GLuint binding, size_t bytes, const void* data = nullptr);
  void storageBarrier();
  // PassRunner::compositeOntoBackgrounds: `resolve` is GLSL defining
  //   bool resolve(vec3 background0, vec3 background1, out vec3 result0, out vec3 result1)
  // with the pixel's "opaque" and "analysis" colours; what it returns goes into them with alpha 1,
  // or nothing where it returns false. Both are read from copies (scratch "background_opaque",
  // "background_analysis"), since the pass writes them.
  void compositeOntoBackgrounds(const std::string& resolve, const std::vector<GlInput>& inputs);

  // With timing on, each pass above runs inside a GL_TIME_ELAPSED timer query (the driver's own
  // clock of the pass). takePassTimes, after the frame's glFinish, returns the frame's passes in
  // order as (kind, ms): "opaque" (its clears included), "transparent", "full-screen", "composite".
  void timePasses(bool on) { timing_ = on; }
  std::vector<std::pair<std::string, double>> takePassTimes();

 private:
  class PassQuery {  // one timer query around a pass, when timing
   public:
    PassQuery(GlFrame& frame, const char* kind);
    ~PassQuery();
    PassQuery(const PassQuery&) = delete;
    PassQuery& operator=(const PassQuery&) = delete;

   private:
    GlFrame& frame_;
    bool active_;
  };
  void fullscreenDraw(const std::string& main, const std::vector<std::string>& colours, const PipelineState& state,
                      const std::vector<GlInput>& inputs);
  struct Texture {
    GLuint id = 0;
    bool isDepth = false;
    Format format{};
  };
  struct Part {
    GLuint vao = 0, vertices = 0, indices = 0;
    GLsizei indexCount = 0;
    bool transparent = false, particles = false;
    GLuint texture = 0;        // the object's texture with its levels and sampler state; 0: none
    float alphaTest = -1.0f;   // the object's alpha_test; < 0: none
    int objectIndex = 0;       // the object's index in the scene (FragmentInput::drawId): uniform `objectIndex`
    int index = 0;             // the part's place in the submission order: uniform `partIndex`
  };
  // The object's texture as a GL texture object (every level as oitref holds it, so both sample
  // the same texels) with the sampler's filters and wraps.
  GLuint uploadTexture(const SceneObject& object);
  GLuint program(const std::string& vertex, const std::string& main, size_t colourCount,
                 const std::vector<GlInput>& inputs);
  void bindTargets(const std::vector<std::string>& colours, const std::string& depth);
  void bindInputs(GLuint program, const std::vector<GlInput>& inputs);
  void drawParts(GLuint program, bool transparent, bool everything);
  struct PartUniforms {
    GLint particles, textured, alphaTest, objectIndex, partIndex;
  };
  PartUniforms partUniforms(GLuint program);            // the locations; the texture unit set
  void usePart(const PartUniforms& u, const Part& part);  // the part's uniforms, texture and vertex array
  const Texture& texture(const std::string& name) const;

  const GlContext& context_;
  const GlFunctions& gl_;
  const FrameContext& frame_;
  std::map<std::string, Texture> textures_;
  std::map<std::string, GLuint> framebuffers_;
  std::map<std::string, GLuint> programs_;
  std::vector<Part> parts_;
  std::vector<GLuint> storage_;
  GLuint emptyVao_ = 0;
  bool timing_ = false;
  std::vector<GLuint> queries_;           // timer queries, reused frame after frame
  std::vector<std::string> queryKinds_;   // this frame's timed passes, in order
};

}  // namespace oitref::glcheck
