// The calls an oitref GL trace holds (gpucapture/gl_trace.h), shared by the recording and the
// replaying half. Private to gpucapture.
#pragma once

#include <cstdint>

namespace oitref::glcheck::trace {

// The calls a trace holds. Queries (glGet*, glCheckFramebufferStatus) change nothing and are not
// recorded; the replay checks compile and link status itself.
enum class Op : uint16_t {
  Blob = 1, Enable, Disable, Enablei, Disablei, Viewport, Finish, PixelStorei, ReadPixels, ReadBuffer,
  GenTextures, DeleteTextures, BindTexture, ActiveTexture, TexStorage2D, TexParameteri, GenFramebuffers,
  DeleteFramebuffers, BindFramebuffer, FramebufferTexture2D, DrawBuffers, ClearBufferfv, ClearBufferfi, ColorMaski,
  DepthFunc, DepthMask, BlendEquationSeparatei, BlendFuncSeparatei, BlendColor, CreateShader, ShaderSource,
  CompileShader, DeleteShader, CreateProgram, AttachShader, LinkProgram, DeleteProgram, UseProgram,
  GetUniformLocation, Uniform1i, Uniform1f, Uniform4fv, GenBuffers, DeleteBuffers, BindBuffer, BufferData,
  BindBufferBase, GenVertexArrays, DeleteVertexArrays, BindVertexArray, DrawArrays, DrawElements,
  VertexAttribPointer, EnableVertexAttribArray, CopyImageSubData, MemoryBarrier, ProvokingVertex,
  CullFace, FrontFace, TexSubImage2D  // appended: traces recorded before them still replay
};

inline constexpr char kMagic[8] = {'O', 'I', 'T', 'R', 'G', 'L', 'T', '1'};

}  // namespace oitref::glcheck::trace
