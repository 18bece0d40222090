// The OpenGL 4.3 core entry points glcheck uses, loaded through eglGetProcAddress (EGL 1.5 returns
// core functions too), so oitref links only libEGL and no GL library at all.
#pragma once

#include <GL/glcorearb.h>

#define OITREF_GL_FUNCTIONS(X)                                                                          \
  X(PFNGLGETSTRINGPROC, GetString)                                                                      \
  X(PFNGLGETERRORPROC, GetError)                                                                        \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                                  \
  X(PFNGLENABLEPROC, Enable)                                                                            \
  X(PFNGLDISABLEPROC, Disable)                                                                          \
  X(PFNGLENABLEIPROC, Enablei)                                                                          \
  X(PFNGLDISABLEIPROC, Disablei)                                                                        \
  X(PFNGLVIEWPORTPROC, Viewport)                                                                        \
  X(PFNGLFINISHPROC, Finish)                                                                            \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                                  \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                                                    \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                                                    \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                                                  \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                                            \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                                                  \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                                              \
  X(PFNGLTEXSTORAGE2DPROC, TexStorage2D)                                                                \
  X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                                                              \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                                              \
  X(PFNGLGETTEXLEVELPARAMETERIVPROC, GetTexLevelParameteriv)                                            \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                                          \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                                    \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                          \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                                                \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                            \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                                                  \
  X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                                                              \
  X(PFNGLCLEARBUFFERFIPROC, ClearBufferfi)                                                              \
  X(PFNGLCOLORMASKIPROC, ColorMaski)                                                                    \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                                      \
  X(PFNGLCULLFACEPROC, CullFace)                                                                        \
  X(PFNGLFRONTFACEPROC, FrontFace)                                                                      \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                                                      \
  X(PFNGLBLENDEQUATIONSEPARATEIPROC, BlendEquationSeparatei)                                            \
  X(PFNGLBLENDFUNCSEPARATEIPROC, BlendFuncSeparatei)                                                    \
  X(PFNGLBLENDCOLORPROC, BlendColor)                                                                    \
  X(PFNGLCREATESHADERPROC, CreateShader)                                                                \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                                \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                                              \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                                  \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                                        \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                                                \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                                              \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                                                \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                                  \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                                \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                                      \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                                              \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                                                    \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                                    \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                                                      \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                                                      \
  X(PFNGLUNIFORM4FVPROC, Uniform4fv)                                                                    \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                                                    \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                              \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                                                    \
  X(PFNGLBUFFERDATAPROC, BufferData)                                                                    \
  X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                                                            \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                                          \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                                    \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                          \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                                    \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                                                                \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                                  \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                          \
  X(PFNGLCOPYIMAGESUBDATAPROC, CopyImageSubData)                                                        \
  X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                                                              \
  X(PFNGLPROVOKINGVERTEXPROC, ProvokingVertex)                                                          \
  X(PFNGLGENQUERIESPROC, GenQueries)                                                                    \
  X(PFNGLDELETEQUERIESPROC, DeleteQueries)                                                              \
  X(PFNGLBEGINQUERYPROC, BeginQuery)                                                                    \
  X(PFNGLENDQUERYPROC, EndQuery)                                                                        \
  X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)

namespace oitref::glcheck {

struct GlFunctions {
#define OITREF_GL_MEMBER(type, name) type name = nullptr;
  OITREF_GL_FUNCTIONS(OITREF_GL_MEMBER)
#undef OITREF_GL_MEMBER
};

}  // namespace oitref::glcheck
