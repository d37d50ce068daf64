#pragma once
/// OpenGL without a display: an OSMesa core-profile context, and the GL entry points sscs uses,
/// loaded at run time. libOSMesa is opened with dlopen, so a machine without it gets a clear
/// RenderUnavailable error (the CLI's exit 3), not a loader failure before main().
#include <GL/glcorearb.h>

#include <stdexcept>
#include <string>

namespace sscs::gl {

/// OSMesa (or an entry point) is missing: rendering cannot run on this machine.
struct RenderUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The GL functions sscs calls, as pointers filled from OSMesaGetProcAddress.
#define SSCS_GL_FUNCTIONS(X)                                                                               \
  X(PFNGLGETSTRINGPROC, GetString)                                                                         \
  X(PFNGLGETERRORPROC, GetError)                                                                           \
  X(PFNGLENABLEPROC, Enable)                                                                               \
  X(PFNGLDISABLEPROC, Disable)                                                                             \
  X(PFNGLCULLFACEPROC, CullFace)                                                                           \
  X(PFNGLVIEWPORTPROC, Viewport)                                                                           \
  X(PFNGLCLEARCOLORPROC, ClearColor)                                                                       \
  X(PFNGLCLEARPROC, Clear)                                                                                 \
  X(PFNGLFINISHPROC, Finish)                                                                               \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                                                       \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                                     \
  X(PFNGLLINEWIDTHPROC, LineWidth)                                                                         \
  X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                                                                 \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                                                                         \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                                       \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                                                       \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                                 \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                                                       \
  X(PFNGLBUFFERDATAPROC, BufferData)                                                                       \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                                             \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                                       \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                             \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                             \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                                     \
  X(PFNGLCREATESHADERPROC, CreateShader)                                                                   \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                                   \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                                                 \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                                     \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                                           \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                                                   \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                                                 \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                                                   \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                                     \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                                   \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                                         \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                                                 \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                                                       \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                                       \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                                                           \
  X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                                                           \
  X(PFNGLUNIFORM3FPROC, Uniform3f)                                                                         \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                                             \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                                       \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                             \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                                             \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                               \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                                                           \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                                     \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                                           \
  X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample)                               \
  X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer)                                                             \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                                                     \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                                               \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                                                     \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                                                       \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                                                 \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                                                   \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                                                 \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                                                         \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                                                         \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                                                         \
  X(PFNGLDRAWBUFFERPROC, DrawBuffer)                                                                       \
  X(PFNGLREADBUFFERPROC, ReadBuffer)

struct Api {
#define SSCS_GL_MEMBER(type, name) type name = nullptr;
  SSCS_GL_FUNCTIONS(SSCS_GL_MEMBER)
#undef SSCS_GL_MEMBER
};

/// An offscreen OpenGL 3.3+ core context drawing into its own width x height RGBA buffer
/// (sscs renders into framebuffer objects of that size). One per thread; current on creation.
class Context {
 public:
  Context(int width, int height);  ///< throws RenderUnavailable
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  const Api& api() const { return api_; }
  std::string renderer() const;  ///< "llvmpipe (LLVM 15, 256 bits)", "4.5 (Core Profile) ..."

 private:
  void* context_ = nullptr;
  std::string buffer_;
  Api api_;
};

}  // namespace sscs::gl
