#include "render/gl.h"

#include <dlfcn.h>

#include <cstdlib>
#include <vector>

#include <fmt/format.h>

namespace sscs::gl {

namespace {

// From GL/osmesa.h, which cannot be included beside glcorearb.h (it pulls in GL/gl.h).
constexpr int kOsmesaFormat = 0x22, kOsmesaDepthBits = 0x30, kOsmesaStencilBits = 0x31, kOsmesaAccumBits = 0x32,
              kOsmesaProfile = 0x33, kOsmesaCoreProfile = 0x34, kOsmesaMajor = 0x36, kOsmesaMinor = 0x37;
using CreateContextAttribs = void* (*)(const int* attribs, void* share);
using MakeCurrent = unsigned char (*)(void* ctx, void* buffer, GLenum type, GLsizei width, GLsizei height);
using DestroyContext = void (*)(void* ctx);
using GetProcAddress = void* (*)(const char* name);

struct OsMesa {
  void* lib = nullptr;
  CreateContextAttribs create = nullptr;
  MakeCurrent make_current = nullptr;
  DestroyContext destroy = nullptr;
  GetProcAddress proc = nullptr;
};

/// libOSMesa, opened once per process.
const OsMesa& osmesa() {
  static const OsMesa lib = [] {
    OsMesa m;
    // $SSCS_OSMESA names the library to use instead (another Mesa build; tests of its absence).
    std::vector<std::string> names = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"};
    if (const char* chosen = std::getenv("SSCS_OSMESA")) names = {chosen};
    for (const std::string& name : names)
      if ((m.lib = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL))) break;
    if (!m.lib) return m;
    m.create = reinterpret_cast<CreateContextAttribs>(dlsym(m.lib, "OSMesaCreateContextAttribs"));
    m.make_current = reinterpret_cast<MakeCurrent>(dlsym(m.lib, "OSMesaMakeCurrent"));
    m.destroy = reinterpret_cast<DestroyContext>(dlsym(m.lib, "OSMesaDestroyContext"));
    m.proc = reinterpret_cast<GetProcAddress>(dlsym(m.lib, "OSMesaGetProcAddress"));
    return m;
  }();
  return lib;
}

}  // namespace

Context::Context(int width, int height) {
  const OsMesa& m = osmesa();
  if (!m.lib)
    throw RenderUnavailable(fmt::format(
        "rendering needs OSMesa ({}, Debian package libosmesa6), which cannot be loaded: {}; install it, or "
        "simulate with --no-frames",
        std::getenv("SSCS_OSMESA") ? std::getenv("SSCS_OSMESA") : "libOSMesa.so.8", dlerror()));
  if (!m.create || !m.make_current || !m.destroy || !m.proc)
    throw RenderUnavailable("the installed libOSMesa lacks OSMesaCreateContextAttribs (Mesa 11.2 or later is needed)");
  const int attribs[] = {kOsmesaFormat, 0x1908 /* GL_RGBA */, kOsmesaDepthBits, 24, kOsmesaStencilBits, 0,
                         kOsmesaAccumBits, 0, kOsmesaProfile, kOsmesaCoreProfile, kOsmesaMajor, 3, kOsmesaMinor, 3, 0};
  context_ = m.create(attribs, nullptr);
  if (!context_) throw RenderUnavailable("OSMesa could not create an OpenGL 3.3 core context");
  buffer_.resize(static_cast<size_t>(width) * height * 4);
  if (!m.make_current(context_, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
    m.destroy(context_);
    throw RenderUnavailable("OSMesa could not make its context current");
  }
#define SSCS_GL_LOAD(type, name)                                                            \
  api_.name = reinterpret_cast<type>(m.proc("gl" #name));                                   \
  if (!api_.name) {                                                                         \
    m.destroy(context_);                                                                    \
    throw RenderUnavailable(fmt::format("OSMesa's OpenGL lacks gl{}", #name));               \
  }
  SSCS_GL_FUNCTIONS(SSCS_GL_LOAD)
#undef SSCS_GL_LOAD
}

Context::~Context() {
  if (context_) osmesa().destroy(context_);
}

std::string Context::renderer() const {
  auto text = [&](GLenum e) {
    const GLubyte* s = api_.GetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return fmt::format("{}, OpenGL {}", text(GL_RENDERER), text(GL_VERSION));
}

}  // namespace sscs::gl
